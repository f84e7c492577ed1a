/* The CPython binding of libdpoints: a thin layer that the package dpoints
 * (python/dpoints/__init__.py) wraps in numpy. It uses only the public API
 * and the buffer protocol, so building it needs no numpy headers: arrays come
 * in as C-contiguous float32 buffers and go out as bytearrays numpy views
 * without a copy. Long calls release the GIL; the progress callback takes it
 * back to run the user's callback and to notice Ctrl-C. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include "dpoints.h"

#include <stddef.h>
#include <stdlib.h>
#include <string.h>

static PyObject *dp_py_error; /* (message, status) -> exception, set by the package at import */

/* ------------------------------------------------------------ parameters */

typedef enum { P_DOUBLE, P_INT, P_SIZE, P_U64, P_VEC3 } param_type;

typedef struct param_field {
	const char *name; /* the keyword: "<stage>_<field>" */
	param_type type;
	size_t offset;    /* in dp_params */
} param_field;

#define F(stage, field, type) {#stage "_" #field, type, offsetof(dp_params, stage.field)}
/* Every field of dp_params: the keywords of dpoints.consolidate. Enums are
 * int-sized here (checked below) and named in Python. */
static const param_field PARAMS[] = {
	F(wlop, samples, P_SIZE),         F(wlop, ratio, P_DOUBLE),
	F(wlop, h, P_DOUBLE),             F(wlop, h_factor, P_DOUBLE),
	F(wlop, mu, P_DOUBLE),            F(wlop, max_iters, P_INT),
	F(wlop, tol, P_DOUBLE),           F(wlop, stall_tol, P_DOUBLE),
	F(wlop, window, P_INT),           F(wlop, min_drop, P_DOUBLE),
	F(wlop, theta_k, P_DOUBLE),       F(wlop, weight, P_INT),
	F(wlop, sqrt_density, P_INT),     F(wlop, seed, P_U64),
	F(normals, k, P_INT),             F(normals, k_graph, P_INT),
	F(normals, use_viewpoint, P_INT), F(normals, viewpoint, P_VEC3),
	F(sink, sigma_p, P_DOUBLE),       F(sink, settle_radius_r, P_DOUBLE),
	F(sink, front_factor, P_DOUBLE),  F(sink, omega_deg, P_DOUBLE),
	F(sink, first_step_r, P_DOUBLE),  F(sink, slow_fraction, P_DOUBLE),
	F(sink, max_iters, P_INT),        F(sink, medial_margin_r, P_DOUBLE),
	F(sink, meet_shift_r, P_DOUBLE),   F(sink, slow_margin_r, P_DOUBLE),
	F(sink, width_factor, P_DOUBLE),  F(sink, flat_angle_deg, P_DOUBLE),
	F(sink, wall_min_r, P_DOUBLE),     F(sink, medial_fraction, P_DOUBLE),
	F(sink, medial_fraction_cap_r, P_DOUBLE),
	F(skeleton, sigma_q, P_DOUBLE),   F(skeleton, eps, P_DOUBLE),
	F(skeleton, mu, P_DOUBLE),        F(skeleton, cutoff, P_DOUBLE),
	F(skeleton, min_axis_weight, P_DOUBLE), F(skeleton, across_only, P_INT),
	F(skeleton, max_iters, P_INT),
	F(skeleton, window, P_INT),       F(skeleton, min_drop, P_DOUBLE),
	F(skeleton, min_move_r, P_DOUBLE),
	F(surface, sigma_p, P_DOUBLE),    F(surface, mu_hat, P_DOUBLE),
	F(surface, prior, P_INT),         F(surface, data_along_normal, P_INT),
	F(surface, tangent_floor_r, P_DOUBLE), F(surface, normal_radius_r, P_DOUBLE),
	F(surface, slide_reach_r, P_DOUBLE), F(surface, escape_margin_r, P_DOUBLE),
	F(surface, reattach, P_INT),      F(surface, reattach_radius_r, P_DOUBLE),
	F(surface, end_smoothing_r, P_DOUBLE),
	F(surface, max_iters, P_INT),     F(surface, same_side, P_INT),
	F(surface, orient_by_dpoint, P_INT), F(surface, window, P_INT),
	F(surface, min_drop, P_DOUBLE),   F(surface, min_growth, P_DOUBLE),
	F(surface, min_move_r, P_DOUBLE), F(surface, sheet_points, P_INT),
	F(surface, silhouette, P_INT),    F(surface, silhouette_axis, P_VEC3),
	F(surface, silhouette_grazing, P_DOUBLE), F(surface, silhouette_margin_r, P_DOUBLE),
	F(surface, face_scanner, P_INT),  F(surface, face_scanner_cos, P_DOUBLE),
	F(surface, scanner_side, P_INT),  F(surface, use_viewpoint, P_INT),
	F(surface, viewpoint, P_VEC3),    F(surface, silhouette_edge_margin_r, P_DOUBLE),
	F(refine, coarse_samples, P_SIZE), F(refine, coarse_min, P_SIZE), F(refine, level_factor, P_DOUBLE),
	F(refine, level_iters, P_INT),    F(refine, samples_floor, P_SIZE),
	F(refine, even_rounds, P_INT),    F(refine, even_iters, P_INT),
	F(refine, fill_samples, P_SIZE),
};
#undef F
#define NPARAMS (sizeof PARAMS / sizeof PARAMS[0])

_Static_assert(sizeof(dp_wlop_weight) == sizeof(int) && sizeof(dp_surface_prior) == sizeof(int),
	       "enums are passed as int");

static PyObject *param_get(const dp_params *p, const param_field *f)
{
	const char *base = (const char *)p + f->offset;
	switch (f->type) {
	case P_DOUBLE: return PyFloat_FromDouble(*(const double *)base);
	case P_INT: return PyLong_FromLong(*(const int *)base);
	case P_SIZE: return PyLong_FromSize_t(*(const size_t *)base);
	case P_U64: return PyLong_FromUnsignedLongLong(*(const uint64_t *)base);
	case P_VEC3: {
		const double *v = (const double *)base;
		return Py_BuildValue("(ddd)", v[0], v[1], v[2]);
	}
	}
	return NULL;
}

static int param_set(dp_params *p, const param_field *f, PyObject *value)
{
	char *base = (char *)p + f->offset;
	switch (f->type) {
	case P_DOUBLE: {
		double v = PyFloat_AsDouble(value);
		if (v == -1.0 && PyErr_Occurred())
			return -1;
		*(double *)base = v;
		return 0;
	}
	case P_INT: {
		long v = PyLong_AsLong(value);
		if (v == -1 && PyErr_Occurred())
			return -1;
		if (v < -2147483647L - 1 || v > 2147483647L) {
			PyErr_Format(PyExc_OverflowError, "%s: %ld does not fit an int", f->name, v);
			return -1;
		}
		*(int *)base = (int)v;
		return 0;
	}
	case P_SIZE: {
		size_t v = PyLong_AsSize_t(value);
		if (v == (size_t)-1 && PyErr_Occurred())
			return -1;
		*(size_t *)base = v;
		return 0;
	}
	case P_U64: {
		unsigned long long v = PyLong_AsUnsignedLongLong(value);
		if (v == (unsigned long long)-1 && PyErr_Occurred())
			return -1;
		*(uint64_t *)base = v;
		return 0;
	}
	case P_VEC3: {
		double *v = (double *)base;
		return PyArg_ParseTuple(value, "ddd", &v[0], &v[1], &v[2]) ? 0 : -1;
	}
	}
	return -1;
}

/* dict of every keyword and its library default */
static PyObject *py_default_params(PyObject *self, PyObject *args)
{
	(void)self;
	(void)args;
	dp_params p;
	dp_params_default(&p);
	PyObject *d = PyDict_New();
	if (!d)
		return NULL;
	for (size_t i = 0; i < NPARAMS; i++) {
		PyObject *v = param_get(&p, &PARAMS[i]);
		if (!v || PyDict_SetItemString(d, PARAMS[i].name, v) < 0) {
			Py_XDECREF(v);
			Py_DECREF(d);
			return NULL;
		}
		Py_DECREF(v);
	}
	return d;
}

/* Fills p from the defaults and a dict of keywords; unknown keys are refused. */
static int params_from_dict(dp_params *p, PyObject *dict)
{
	dp_params_default(p);
	if (!dict || dict == Py_None)
		return 0;
	PyObject *key, *value;
	Py_ssize_t pos = 0;
	while (PyDict_Next(dict, &pos, &key, &value)) {
		const char *name = PyUnicode_AsUTF8(key);
		if (!name)
			return -1;
		size_t i = 0;
		while (i < NPARAMS && strcmp(PARAMS[i].name, name) != 0)
			i++;
		if (i == NPARAMS) {
			PyErr_Format(PyExc_TypeError, "unknown parameter '%s'", name);
			return -1;
		}
		if (param_set(p, &PARAMS[i], value) < 0)
			return -1;
	}
	return 0;
}

/* ---------------------------------------------------------------- errors */

/* Sets the exception the package's factory makes of a message and a status
 * (dpoints.Error, or its subclass for the status). */
static PyObject *raise(const dp_error *err)
{
	const char *msg = err->message[0] ? err->message : dp_status_string(err->status);
	if (!dp_py_error) {
		PyErr_SetString(PyExc_RuntimeError, msg);
		return NULL;
	}
	PyObject *exc = PyObject_CallFunction(dp_py_error, "si", msg, (int)err->status);
	if (exc) {
		PyErr_SetObject((PyObject *)Py_TYPE(exc), exc);
		Py_DECREF(exc);
	}
	return NULL;
}

/* -------------------------------------------------------------- contexts */

static void context_destroy(PyObject *capsule)
{
	dp_context_free(PyCapsule_GetPointer(capsule, "dpoints.context"));
}

static PyObject *py_context(PyObject *self, PyObject *args)
{
	(void)self;
	int backend;
	const char *device = NULL;
	if (!PyArg_ParseTuple(args, "iz", &backend, &device))
		return NULL;
	dp_error err = {0};
	dp_context *ctx = NULL;
	dp_status st;
	/* builds the OpenCL program: seconds */
	Py_BEGIN_ALLOW_THREADS
	st = dp_context_create(&ctx, backend ? DP_BACKEND_REF : DP_BACKEND_CL, device, &err);
	Py_END_ALLOW_THREADS
	if (st != DP_OK)
		return raise(&err);
	PyObject *cap = PyCapsule_New(ctx, "dpoints.context", context_destroy);
	if (!cap)
		dp_context_free(ctx);
	return cap;
}

static PyObject *py_context_set_threads(PyObject *self, PyObject *args)
{
	(void)self;
	PyObject *cap;
	int threads;
	if (!PyArg_ParseTuple(args, "Oi", &cap, &threads))
		return NULL;
	dp_context *ctx = PyCapsule_GetPointer(cap, "dpoints.context");
	if (!ctx)
		return NULL;
	dp_context_set_threads(ctx, threads);
	Py_RETURN_NONE;
}

static PyObject *py_context_device(PyObject *self, PyObject *args)
{
	(void)self;
	PyObject *cap;
	if (!PyArg_ParseTuple(args, "O", &cap))
		return NULL;
	dp_context *ctx = PyCapsule_GetPointer(cap, "dpoints.context");
	return ctx ? PyUnicode_FromString(dp_context_device_name(ctx)) : NULL;
}

/* -------------------------------------------------------------- progress */

typedef struct progress_state {
	PyObject *callback; /* may be None */
	int failed;         /* a Python exception is pending (KeyboardInterrupt, the callback's own) */
	int cancelled;      /* the callback returned true */
} progress_state;

static int progress_trampoline(void *user, const char *stage, int iteration, double value, double elapsed)
{
	progress_state *ps = user;
	PyGILState_STATE g = PyGILState_Ensure();
	int stop = 0;
	/* Ctrl-C: the interpreter's handler only runs when asked, and the GIL was released */
	if (PyErr_CheckSignals() < 0) {
		ps->failed = 1;
		stop = 1;
	} else if (ps->callback != Py_None) {
		PyObject *r = PyObject_CallFunction(ps->callback, "sidd", stage, iteration, value, elapsed);
		if (!r) {
			ps->failed = 1;
			stop = 1;
		} else {
			int t = PyObject_IsTrue(r);
			Py_DECREF(r);
			if (t < 0) {
				ps->failed = 1;
				stop = 1;
			} else if (t) {
				ps->cancelled = 1;
				stop = 1;
			}
		}
	}
	PyGILState_Release(g);
	return stop;
}

/* ----------------------------------------------------------------- clouds */

/* A C-contiguous (n, 3) float32 buffer as a cloud (positions copied to SoA). */
static int cloud_from_buffer(PyObject *obj, dp_cloud *cloud)
{
	Py_buffer view;
	if (PyObject_GetBuffer(obj, &view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | PyBUF_ND) < 0)
		return -1;
	int ok = view.ndim == 2 && view.shape[1] == 3 && view.itemsize == 4 && view.format &&
		 strcmp(view.format, "f") == 0;
	if (!ok) {
		PyBuffer_Release(&view);
		PyErr_SetString(PyExc_ValueError, "points must be a C-contiguous (N, 3) float32 buffer");
		return -1;
	}
	size_t n = (size_t)view.shape[0];
	dp_error err = {0};
	if (dp_cloud_alloc(cloud, n, 0, &err) != DP_OK) {
		PyBuffer_Release(&view);
		raise(&err);
		return -1;
	}
	const float *xyz = view.buf;
	for (size_t i = 0; i < n; i++) {
		cloud->x[i] = xyz[3 * i];
		cloud->y[i] = xyz[3 * i + 1];
		cloud->z[i] = xyz[3 * i + 2];
	}
	PyBuffer_Release(&view);
	return 0;
}

/* n interleaved triples of (a, b, c) as a bytearray of 3n float32; None when a is NULL. */
static PyObject *triples(const float *a, const float *b, const float *c, size_t n)
{
	if (!a)
		Py_RETURN_NONE;
	PyObject *out = PyByteArray_FromStringAndSize(NULL, (Py_ssize_t)(3 * n * sizeof(float)));
	if (!out)
		return NULL;
	float *o = (float *)PyByteArray_AS_STRING(out);
	for (size_t i = 0; i < n; i++) {
		o[3 * i] = a[i];
		o[3 * i + 1] = b[i];
		o[3 * i + 2] = c[i];
	}
	return out;
}

static PyObject *bytes_of(const void *data, size_t size)
{
	if (!data)
		Py_RETURN_NONE;
	return PyByteArray_FromStringAndSize(data, (Py_ssize_t)size);
}

/* {"points", "normals", "faces", "colors"} of a cloud */
static PyObject *cloud_dict(const dp_cloud *c)
{
	return Py_BuildValue("{s:N,s:N,s:N,s:N}", "points", triples(c->x, c->y, c->z, c->n), "normals",
			     triples(c->nx, c->ny, c->nz, c->n), "faces",
			     c->faces ? bytes_of(c->faces, 3 * c->nfaces * sizeof(uint32_t)) : Py_BuildValue(""),
			     "colors", bytes_of(c->rgb, 3 * c->n));
}

static PyObject *py_read(PyObject *self, PyObject *args)
{
	(void)self;
	PyObject *path_obj;
	int mesh;
	if (!PyArg_ParseTuple(args, "O&p", PyUnicode_FSConverter, &path_obj, &mesh))
		return NULL;
	dp_error err = {0};
	dp_cloud c = {0};
	dp_status st;
	const char *path = PyBytes_AS_STRING(path_obj);
	Py_BEGIN_ALLOW_THREADS
	st = dp_cloud_read(path, &c, mesh ? DP_READ_MESH : DP_READ_POINTS, &err);
	Py_END_ALLOW_THREADS
	Py_DECREF(path_obj);
	if (st != DP_OK)
		return raise(&err);
	PyObject *d = cloud_dict(&c);
	dp_cloud_free(&c);
	return d;
}

/* ---------------------------------------------------------------- results */

static void result_destroy(PyObject *capsule)
{
	dp_result *r = PyCapsule_GetPointer(capsule, "dpoints.result");
	dp_result_free(r);
	free(r);
}

/* Runs `call` with the GIL released and the progress trampoline installed;
 * sorts out which exception a stop raises. */
#define RUN_WITH_PROGRESS(ctx, ps, st, call)                                  \
	do {                                                                   \
		dp_context_set_progress(ctx, progress_trampoline, &(ps));       \
		Py_BEGIN_ALLOW_THREADS                                         \
		(st) = (call);                                                 \
		Py_END_ALLOW_THREADS                                           \
		dp_context_set_progress(ctx, NULL, NULL);                       \
	} while (0)

static PyObject *stopped(const progress_state *ps, const dp_error *err)
{
	if (ps->failed)
		return NULL; /* the pending exception: KeyboardInterrupt or the callback's */
	return raise(err);
}

static PyObject *py_consolidate(PyObject *self, PyObject *args)
{
	(void)self;
	PyObject *cap, *points, *params_dict, *callback;
	if (!PyArg_ParseTuple(args, "OOOO", &cap, &points, &params_dict, &callback))
		return NULL;
	dp_context *ctx = PyCapsule_GetPointer(cap, "dpoints.context");
	if (!ctx)
		return NULL;
	dp_params params;
	if (params_from_dict(&params, params_dict) < 0)
		return NULL;
	dp_cloud in = {0};
	if (cloud_from_buffer(points, &in) < 0)
		return NULL;
	dp_result *res = calloc(1, sizeof *res);
	if (!res) {
		dp_cloud_free(&in);
		return PyErr_NoMemory();
	}
	dp_error err = {0};
	progress_state ps = {callback, 0, 0};
	dp_status st;
	RUN_WITH_PROGRESS(ctx, ps, st, dp_consolidate(ctx, &in, &params, res, &err));
	dp_cloud_free(&in);
	if (st != DP_OK) {
		free(res);
		return stopped(&ps, &err);
	}
	PyObject *capsule = PyCapsule_New(res, "dpoints.result", result_destroy);
	if (!capsule) {
		dp_result_free(res);
		free(res);
	}
	return capsule;
}

static PyObject *py_result_arrays(PyObject *self, PyObject *args)
{
	(void)self;
	PyObject *cap;
	if (!PyArg_ParseTuple(args, "O", &cap))
		return NULL;
	const dp_result *r = PyCapsule_GetPointer(cap, "dpoints.result");
	if (!r)
		return NULL;
	size_t n = r->surface.n;
	return Py_BuildValue("{s:N,s:N,s:N,s:N,s:N,s:N,s:N,s:N,s:N,s:d}", "colors", bytes_of(r->surface.rgb, 3 * n),
			     "surface",
			     triples(r->surface.x, r->surface.y, r->surface.z, n), "normals",
			     triples(r->surface.nx, r->surface.ny, r->surface.nz, n), "skeleton",
			     triples(r->skeleton.x, r->skeleton.y, r->skeleton.z, n), "length",
			     bytes_of(r->length, n * sizeof(float)), "eta", bytes_of(r->eta, n * sizeof(float)),
			     "wlop", cloud_dict(&r->wlop), "anchors", cloud_dict(&r->anchors), "settled",
			     bytes_of(r->settled_by, r->anchors.n), "r", r->r);
}

static PyObject *py_result_report(PyObject *self, PyObject *args)
{
	(void)self;
	PyObject *cap;
	const char *input_name = NULL;
	if (!PyArg_ParseTuple(args, "Oz", &cap, &input_name))
		return NULL;
	const dp_result *r = PyCapsule_GetPointer(cap, "dpoints.result");
	if (!r)
		return NULL;
	dp_write_options wo;
	dp_write_options_default(&wo);
	wo.input_name = input_name;
	dp_error err = {0};
	char *json = NULL;
	if (dp_result_report(r, &wo, &json, &err) != DP_OK)
		return raise(&err);
	PyObject *s = PyUnicode_FromString(json);
	free(json);
	return s;
}

static PyObject *py_result_write(PyObject *self, PyObject *args)
{
	(void)self;
	PyObject *cap, *dir_obj, *input;
	unsigned flags;
	int up_axis;
	const char *input_name = NULL;
	if (!PyArg_ParseTuple(args, "OO&IiOz", &cap, PyUnicode_FSConverter, &dir_obj, &flags, &up_axis, &input,
			      &input_name))
		return NULL;
	const dp_result *r = PyCapsule_GetPointer(cap, "dpoints.result");
	dp_cloud in = {0};
	if (!r || (input != Py_None && cloud_from_buffer(input, &in) < 0)) {
		Py_DECREF(dir_obj);
		return NULL;
	}
	dp_write_options wo;
	dp_write_options_default(&wo);
	wo.flags = flags;
	wo.up_axis = up_axis;
	wo.input = input != Py_None ? &in : NULL;
	wo.input_name = input_name;
	dp_error err = {0};
	dp_status st;
	const char *dir = PyBytes_AS_STRING(dir_obj);
	Py_BEGIN_ALLOW_THREADS
	st = dp_result_write(r, dir, &wo, &err);
	Py_END_ALLOW_THREADS
	Py_DECREF(dir_obj);
	dp_cloud_free(&in);
	if (st != DP_OK)
		return raise(&err);
	Py_RETURN_NONE;
}

/* ------------------------------------------------------------------- WLOP */

static PyObject *py_wlop(PyObject *self, PyObject *args)
{
	(void)self;
	PyObject *cap, *points, *params_dict, *callback;
	int normals;
	if (!PyArg_ParseTuple(args, "OOOOp", &cap, &points, &params_dict, &callback, &normals))
		return NULL;
	dp_context *ctx = PyCapsule_GetPointer(cap, "dpoints.context");
	if (!ctx)
		return NULL;
	dp_params params;
	if (params_from_dict(&params, params_dict) < 0)
		return NULL;
	dp_cloud in = {0}, out = {0};
	if (cloud_from_buffer(points, &in) < 0)
		return NULL;
	dp_error err = {0};
	dp_wlop_stats stats;
	progress_state ps = {callback, 0, 0};
	dp_status st;
	RUN_WITH_PROGRESS(ctx, ps, st, dp_wlop(ctx, &in, &params.wlop, &out, &stats, &err));
	size_t dense = 0, turned = 0;
	if (st == DP_OK && normals) {
		Py_BEGIN_ALLOW_THREADS
		st = dp_estimate_normals(&out, &params.normals, &err);
		Py_END_ALLOW_THREADS
		if (st == DP_OK)
			RUN_WITH_PROGRESS(ctx, ps, st,
					  dp_orient_from_denser(ctx, &in, &params.wlop, &params.normals,
								DP_ORIENT_DENSE_SAMPLES, &out, &dense, &turned, &err));
	}
	dp_cloud_free(&in);
	if (st != DP_OK) {
		dp_cloud_free(&out);
		return stopped(&ps, &err);
	}
	PyObject *d = cloud_dict(&out);
	dp_cloud_free(&out);
	if (!d)
		return NULL;
	PyObject *s = Py_BuildValue("{s:n,s:d,s:i,s:O,s:O,s:d,s:d,s:n,s:n}", "samples", (Py_ssize_t)stats.samples,
				    "h", stats.h, "iterations", stats.iterations, "converged",
				    stats.converged ? Py_True : Py_False, "stalled", stats.stalled ? Py_True : Py_False,
				    "last_mean_move_h", stats.last_mean_move, "seconds", stats.seconds,
				    "normals_dense_samples", (Py_ssize_t)dense, "normals_turned", (Py_ssize_t)turned);
	if (!s || PyDict_SetItemString(d, "stats", s) < 0) {
		Py_XDECREF(s);
		Py_DECREF(d);
		return NULL;
	}
	Py_DECREF(s);
	return d;
}

/* --------------------------------------------------------------- devices */

static PyObject *py_devices(PyObject *self, PyObject *args)
{
	(void)self;
	(void)args;
	static const char *const types[] = {"cpu", "gpu", "other"};
	dp_error err = {0};
	dp_device_info *list;
	size_t n;
	if (dp_devices(&list, &n, &err) != DP_OK)
		return raise(&err);
	PyObject *out = PyList_New((Py_ssize_t)n);
	for (size_t i = 0; out && i < n; i++) {
		PyObject *d = Py_BuildValue("{s:n,s:s,s:s,s:I,s:K}", "index", (Py_ssize_t)list[i].index, "name",
					    list[i].name, "type", types[list[i].type], "compute_units",
					    list[i].compute_units, "global_mem_bytes",
					    (unsigned long long)list[i].global_mem_bytes);
		if (!d) {
			Py_CLEAR(out);
			break;
		}
		PyList_SET_ITEM(out, (Py_ssize_t)i, d);
	}
	dp_devices_free(list);
	return out;
}

static PyObject *py_version(PyObject *self, PyObject *args)
{
	(void)self;
	(void)args;
	return PyUnicode_FromString(dp_version());
}

static PyObject *py_set_error(PyObject *self, PyObject *args)
{
	(void)self;
	PyObject *cls;
	if (!PyArg_ParseTuple(args, "O", &cls))
		return NULL;
	Py_XINCREF(cls);
	Py_XSETREF(dp_py_error, cls);
	Py_RETURN_NONE;
}

static PyMethodDef methods[] = {
	{"version", py_version, METH_NOARGS, "the library version"},
	{"devices", py_devices, METH_NOARGS, "OpenCL devices as dicts"},
	{"default_params", py_default_params, METH_NOARGS, "every dp_params field and its default"},
	{"context", py_context, METH_VARARGS, "context(backend, device) -> capsule"},
	{"context_device", py_context_device, METH_VARARGS, "the device name of a context"},
	{"context_set_threads", py_context_set_threads, METH_VARARGS, "host threads of a context's later calls"},
	{"read", py_read, METH_VARARGS, "read(path, mesh) -> dict of bytearrays"},
	{"consolidate", py_consolidate, METH_VARARGS, "consolidate(ctx, points, params, progress) -> result"},
	{"result_arrays", py_result_arrays, METH_VARARGS, "the arrays of a result"},
	{"result_report", py_result_report, METH_VARARGS, "report.json of a result, as text"},
	{"result_write", py_result_write, METH_VARARGS, "write a result's folder"},
	{"wlop", py_wlop, METH_VARARGS, "wlop(ctx, points, params, progress, normals) -> dict"},
	{"set_error", py_set_error, METH_VARARGS, "the factory of the exceptions errors raise"},
	{NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_dpoints", "libdpoints binding", -1, methods,
				    NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__dpoints(void)
{
	PyObject *m = PyModule_Create(&module);
	if (m && PyModule_AddIntConstant(m, "WRITE_ASCII", DP_WRITE_ASCII) == 0 &&
	    PyModule_AddIntConstant(m, "WRITE_STAGES", DP_WRITE_STAGES) == 0 &&
	    PyModule_AddIntConstant(m, "WRITE_RENDER", DP_WRITE_RENDER) == 0 &&
	    PyModule_AddIntConstant(m, "ERR_CANCELLED", DP_ERR_CANCELLED) == 0 &&
	    PyModule_AddIntConstant(m, "SETTLE_FRONT", DP_SETTLE_FRONT) == 0 &&
	    PyModule_AddIntConstant(m, "SETTLE_FLAT", DP_SETTLE_FLAT) == 0)
		return m;
	Py_XDECREF(m);
	return NULL;
}
