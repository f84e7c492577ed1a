/* Facing the scanner (scanner.h). */
#include "stages/scanner.h"

int dp_scanner_side(size_t n, const float *nx, const float *ny, const float *nz, const float axis[3],
		    double cos_min)
{
	size_t along = 0, against = 0;
	for (size_t i = 0; i < n; i++) {
		double d = (double)nx[i] * axis[0] + (double)ny[i] * axis[1] + (double)nz[i] * axis[2];
		along += d > cos_min;
		against += d < -cos_min;
	}
	size_t fewer = along < against ? along : against;
	if (along + against < DP_SCANNER_MIN_NORMALS ||
	    (double)fewer > DP_SCANNER_MINORITY * (double)(along + against))
		return 0;
	return along >= against ? 1 : -1;
}

size_t dp_scanner_face(size_t n, float *nx, float *ny, float *nz, const float toward[3], double cos_min)
{
	size_t turned = 0;
	for (size_t i = 0; i < n; i++) {
		double d = (double)nx[i] * toward[0] + (double)ny[i] * toward[1] + (double)nz[i] * toward[2];
		if (d < -cos_min) {
			nx[i] = -nx[i];
			ny[i] = -ny[i];
			nz[i] = -nz[i];
			turned++;
		}
	}
	return turned;
}
