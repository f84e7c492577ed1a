#include "core/common.h"

#include <stdlib.h>
#include <string.h>

dp_status dp_cloud_alloc(dp_cloud *cloud, size_t n, int with_normals, dp_error *err)
{
	memset(cloud, 0, sizeof *cloud);
	cloud->n = n;
	cloud->x = dp_alloc_array(n, sizeof(float));
	cloud->y = dp_alloc_array(n, sizeof(float));
	cloud->z = dp_alloc_array(n, sizeof(float));
	if (!cloud->x || !cloud->y || !cloud->z)
		goto nomem;
	if (with_normals && dp_cloud_add_normals(cloud, err) != DP_OK)
		goto nomem;
	return DP_OK;
nomem:
	dp_cloud_free(cloud);
	return dp_fail(err, DP_ERR_NOMEM, "out of memory allocating %zu points", n);
}

dp_status dp_cloud_add_normals(dp_cloud *cloud, dp_error *err)
{
	if (cloud->nx)
		return DP_OK;
	cloud->nx = dp_alloc_array(cloud->n, sizeof(float));
	cloud->ny = dp_alloc_array(cloud->n, sizeof(float));
	cloud->nz = dp_alloc_array(cloud->n, sizeof(float));
	if (!cloud->nx || !cloud->ny || !cloud->nz) {
		free(cloud->nx);
		free(cloud->ny);
		free(cloud->nz);
		cloud->nx = cloud->ny = cloud->nz = NULL;
		return dp_fail(err, DP_ERR_NOMEM, "out of memory allocating normals of %zu points", cloud->n);
	}
	return DP_OK;
}

void dp_cloud_free(dp_cloud *cloud)
{
	if (!cloud)
		return;
	free(cloud->x);
	free(cloud->y);
	free(cloud->z);
	free(cloud->nx);
	free(cloud->ny);
	free(cloud->nz);
	free(cloud->faces);
	free(cloud->rgb);
	free(cloud->intensity);
	memset(cloud, 0, sizeof *cloud);
}

dp_status dp_cloud_copy(dp_cloud *dst, const dp_cloud *src, dp_error *err)
{
	dp_status st = dp_cloud_alloc(dst, src->n, src->nx != NULL, err);
	if (st != DP_OK)
		return st;
	size_t bytes = src->n * sizeof(float);
	memcpy(dst->x, src->x, bytes);
	memcpy(dst->y, src->y, bytes);
	memcpy(dst->z, src->z, bytes);
	if (src->nx) {
		memcpy(dst->nx, src->nx, bytes);
		memcpy(dst->ny, src->ny, bytes);
		memcpy(dst->nz, src->nz, bytes);
	}
	if (src->faces && src->nfaces) {
		dst->faces = dp_alloc_array(3 * src->nfaces, sizeof(uint32_t));
		if (!dst->faces) {
			dp_cloud_free(dst);
			return dp_fail(err, DP_ERR_NOMEM, "out of memory copying %zu faces", src->nfaces);
		}
		memcpy(dst->faces, src->faces, 3 * src->nfaces * sizeof(uint32_t));
		dst->nfaces = src->nfaces;
	}
	if (src->rgb) {
		dst->rgb = dp_alloc_array(3 * src->n, 1);
		if (!dst->rgb) {
			dp_cloud_free(dst);
			return dp_fail(err, DP_ERR_NOMEM, "out of memory copying %zu colours", src->n);
		}
		memcpy(dst->rgb, src->rgb, 3 * src->n);
	}
	if (src->intensity) {
		dst->intensity = dp_alloc_array(src->n, sizeof(float));
		if (!dst->intensity) {
			dp_cloud_free(dst);
			return dp_fail(err, DP_ERR_NOMEM, "out of memory copying %zu intensities", src->n);
		}
		memcpy(dst->intensity, src->intensity, src->n * sizeof(float));
	}
	return DP_OK;
}
