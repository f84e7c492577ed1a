/* WLOP operators; the specification is host/ref/wlop_ref.c. */

__kernel void wlop_density(const uint n, __global const float *qx, __global const float *qy,
			   __global const float *qz, GRID_ARGS, const float h, const float theta_k,
			   const float min_d2, const int sqrt_density, __global float *out)
{
	uint i = get_global_id(0);
	if (i >= n)
		return;
	float px = qx[i], py = qy[i], pz = qz[i];
	float h2 = h * h, sum = 1.0f;
	GRID_FOR(px, py, pz, k)
		float dx = px - gx[k], dy = py - gy[k], dz = pz - gz[k];
		float d2 = dx * dx + dy * dy + dz * dz;
		if (d2 < h2 && d2 >= min_d2)
			sum += exp(-theta_k * d2 / h2);
	GRID_FOR_END
	out[i] = sqrt_density ? sqrt(sum) : sum;
}
