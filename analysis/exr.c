/*
 * exr.c — scanline EXR write and read over the OpenEXR C API (OpenEXRCore).
 * A write defines one scanline part (ZIP, 16 lines a chunk), streams the caller's
 * planar float arrays chunk by chunk through one encode pipeline into a temporary
 * beside the target (bk_out, out.h: the one safe-write module), and renames that
 * file over the target only when every step succeeded; a
 * read mirrors it with a decode pipeline into freshly allocated float planes. The
 * library reports errors through a callback; here the first report of a call is kept
 * and joined to the step that failed, so callers get one line "path: step: detail"
 * and nothing is printed to stderr.
 */
#include "exr.h"
#include "out.h"

#include <openexr.h>

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

/* ---- errors ---------------------------------------------------------------- */

/* Where one call's errors go. */
typedef struct sink {
	const char *path;
	char *err;
	size_t errlen;
	char lib[256]; /* first message the library reported during the call, or "" */
	int failed;    /* err is set: the first failure is the cause, later ones follow */
} sink;

/* The library's callback gets only the context (sometimes NULL), and asking a write
 * context for its user data takes the lock it may hold while reporting. Reports are
 * delivered on the calling thread, so a thread-local pointer is the safe way back. */
static _Thread_local sink *cur_sink;

static void on_exr_error(exr_const_context_t ctx, exr_result_t code, const char *msg)
{
	(void)ctx;
	(void)code;
	if (cur_sink && !cur_sink->lib[0] && msg)
		snprintf(cur_sink->lib, sizeof cur_sink->lib, "%s", msg);
}

/* Library text and strerror() start capitalised ("Unable to", "No such file"); house
 * style is lowercase. A capital is lowered only at the start of a segment and only when
 * a lowercase letter follows, so channel names like "R" survive. One line: no '\n'. */
static void tidy(char *s)
{
	for (char *p = s; *p; p++) {
		if (*p == '\n' || *p == '\r' || *p == '\t')
			*p = ' ';
		int seg = p == s || (p - s >= 2 && p[-1] == ' ' && p[-2] == ':');
		if (seg && isupper((unsigned char)p[0]) && islower((unsigned char)p[1]))
			*p = (char)tolower((unsigned char)*p);
	}
}

static int vfail(sink *k, const char *detail, const char *fmt, va_list ap)
{
	char what[256];
	if (k->failed || !k->err || k->errlen == 0)
		return -1;
	vsnprintf(what, sizeof what, fmt, ap);
	snprintf(k->err, k->errlen, "%s: %s%s%s", k->path, what, detail ? ": " : "",
	         detail ? detail : "");
	size_t skip = strlen(k->path) + 2; /* the path is quoted as given, never tidied */
	if (skip < strlen(k->err))
		tidy(k->err + skip);
	k->failed = 1;
	return -1;
}

/* A failed library call: the library's own report says more than its result code. */
__attribute__((format(printf, 3, 4)))
static int fail_exr(sink *k, exr_result_t rv, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	vfail(k, k->lib[0] ? k->lib : exr_get_default_error_message(rv), fmt, ap);
	va_end(ap);
	return -1;
}

/* A failure of our own (arguments, the file system): no library detail applies. */
__attribute__((format(printf, 2, 3)))
static int fail_msg(sink *k, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	vfail(k, NULL, fmt, ap);
	va_end(ap);
	return -1;
}

static void sink_begin(sink *k, const char *path, char *err, size_t errlen)
{
	memset(k, 0, sizeof *k);
	k->path = path ? path : "(null)";
	k->err = err;
	k->errlen = errlen;
	if (err && errlen)
		err[0] = '\0';
	cur_sink = k;
}

static exr_context_initializer_t ctx_init(void *user)
{
	exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
	init.error_handler_fn = on_exr_error; /* the default one prints to stderr */
	init.user_data = user;
	return init;
}

/* ---- write ------------------------------------------------------------------- */

typedef struct wjob {
	int width, height, nchan, half, nattrs;
	const char *const *names;
	const float *const *data;
	const bk_exr_attr *attrs;
	int fd;
	sink *k;
} wjob;

/* The library would open path itself; the temporary file is already open from
 * bk_out_open (which is what makes its name safe), so hand the library a pwrite. */
static int64_t write_fd(exr_const_context_t ctx, void *user, const void *buf, uint64_t size,
                        uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
	const int fd = *(const int *)user;
	const char *p = buf;
	uint64_t done = 0;
	while (done < size) {
		/* pwrite of more than SSIZE_MAX is implementation-defined; chunks are far smaller */
		size_t n = size - done < ((uint64_t)1 << 30) ? (size_t)(size - done) : (size_t)1 << 30;
		ssize_t got = pwrite(fd, p + done, n, (off_t)(offset + done));
		if (got < 0 && errno == EINTR)
			continue;
		if (got <= 0) {
			error_cb(ctx, EXR_ERR_WRITE_IO, "cannot write: %s",
			         got < 0 ? bk_out_errtext(errno) : "no space written");
			return -1;
		}
		done += (uint64_t)got;
	}
	return (int64_t)done;
}

static int check_attrs(const wjob *j)
{
	if (j->nattrs < 0 || (j->nattrs > 0 && !j->attrs))
		return fail_msg(j->k, "invalid argument: %d attributes given as %p", j->nattrs,
		                (const void *)j->attrs);
	for (int a = 0; a < j->nattrs; a++) {
		const bk_exr_attr *at = &j->attrs[a];
		if (!at->name || !at->name[0])
			return fail_msg(j->k, "invalid argument: attribute %d has no name", a);
		if (at->type != BK_EXR_ATTR_STRING && at->type != BK_EXR_ATTR_INT)
			return fail_msg(j->k, "invalid argument: attribute '%s' has unknown type %d",
			                at->name, (int)at->type);
		if (at->type == BK_EXR_ATTR_STRING && !at->s)
			return fail_msg(j->k, "invalid argument: string attribute '%s' is NULL", at->name);
	}
	return 0;
}

/* Names longer than 31 bytes would not fit bk_exr_image.names on the way back (and
 * need the long-name format, which older readers reject). */
static int check_args(const wjob *j)
{
	if (j->width < 1 || j->height < 1)
		return fail_msg(j->k, "invalid argument: image size %dx%d", j->width, j->height);
	if (j->nchan < 1 || j->nchan > 4)
		return fail_msg(j->k, "invalid argument: %d channels, expected 1 to 4", j->nchan);
	if (!j->names || !j->data)
		return fail_msg(j->k, "invalid argument: no channel names or no channel data");
	for (int c = 0; c < j->nchan; c++) {
		if (!j->names[c] || !j->data[c])
			return fail_msg(j->k, "invalid argument: channel %d has no name or no data", c);
		size_t len = strlen(j->names[c]);
		if (len == 0 || len > 31)
			return fail_msg(j->k, "invalid argument: channel name '%s' is not 1 to 31 bytes",
			                j->names[c]);
	}
	return check_attrs(j);
}

/* A failure of the safe-write module: its message, which names the file already. */
static int fail_out(sink *k, const char *msg)
{
	if (!k->failed && k->err && k->errlen)
		snprintf(k->err, k->errlen, "%s", msg);
	k->failed = 1;
	return -1;
}

static int add_attrs(exr_context_t ctx, int part, const wjob *j)
{
	for (int a = 0; a < j->nattrs; a++) {
		const bk_exr_attr *at = &j->attrs[a];
		exr_result_t rv = at->type == BK_EXR_ATTR_STRING
		                      ? exr_attr_set_string(ctx, part, at->name, at->s)
		                      : exr_attr_set_int(ctx, part, at->name, at->i);
		if (rv != EXR_ERR_SUCCESS)
			return fail_exr(j->k, rv, "setting attribute '%s'", at->name);
	}
	return 0;
}

/* Part, required attributes, channels, extra attributes, then the header is fixed. */
static int define_part(exr_context_t ctx, const wjob *j)
{
	int part = 0;
	exr_result_t rv = exr_add_part(ctx, NULL, EXR_STORAGE_SCANLINE, &part);
	if (rv != EXR_ERR_SUCCESS)
		return fail_exr(j->k, rv, "adding part");
	rv = exr_initialize_required_attr_simple(ctx, part, j->width, j->height,
	                                         EXR_COMPRESSION_ZIP);
	if (rv != EXR_ERR_SUCCESS)
		return fail_exr(j->k, rv, "setting required attributes");
	for (int c = 0; c < j->nchan; c++) {
		/* logarithmic is OpenEXR's default hint (Channel::pLinear = false); only lossy
		 * B44 reads it, so it does not matter for ZIP */
		rv = exr_add_channel(ctx, part, j->names[c], j->half ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT,
		                     EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
		if (rv != EXR_ERR_SUCCESS)
			return fail_exr(j->k, rv, "adding channel '%s'", j->names[c]);
	}
	if (add_attrs(ctx, part, j) != 0)
		return -1;
	rv = exr_write_header(ctx);
	return rv == EXR_ERR_SUCCESS ? 0 : fail_exr(j->k, rv, "writing header");
}

/* The library keeps channels sorted by name, so its channel c is not the caller's c. */
static int user_channel(const wjob *j, const char *name)
{
	for (int c = 0; c < j->nchan; c++)
		if (strcmp(j->names[c], name) == 0)
			return c;
	return -1;
}

/* Points every channel of the pipeline at this chunk's first row of caller data. */
static int aim_encoder(exr_encode_pipeline_t *enc, const exr_chunk_info_t *ci, const wjob *j)
{
	for (int c = 0; c < enc->channel_count; c++) {
		exr_coding_channel_info_t *ch = &enc->channels[c];
		int u = user_channel(j, ch->channel_name);
		if (u < 0)
			return fail_msg(j->k, "channel '%s' lost while writing", ch->channel_name);
		ch->encode_from_ptr = (const uint8_t *)(j->data[u] + (size_t)ci->start_y * (size_t)j->width);
		ch->user_pixel_stride = (int32_t)sizeof(float);
		ch->user_line_stride = (int32_t)sizeof(float) * j->width;
		ch->user_data_type = EXR_PIXEL_FLOAT; /* HALF channels: the library converts */
		ch->user_bytes_per_element = (int16_t)sizeof(float);
	}
	return 0;
}

/* One chunk: its info from the library, then (re)aim the pipeline and run it. The
 * first chunk initialises the pipeline and picks the pack routine, which depends only
 * on the channel types and strides, so later chunks reuse it through update. */
static int write_chunk(exr_context_t ctx, exr_encode_pipeline_t *enc, int y, const wjob *j)
{
	exr_chunk_info_t ci;
	exr_result_t rv = exr_write_scanline_chunk_info(ctx, 0, y, &ci);
	if (rv != EXR_ERR_SUCCESS)
		return fail_exr(j->k, rv, "chunk at line %d", y);
	int first = y == 0;
	rv = first ? exr_encoding_initialize(ctx, 0, &ci, enc) : exr_encoding_update(ctx, 0, &ci, enc);
	if (rv != EXR_ERR_SUCCESS)
		return fail_exr(j->k, rv, "preparing chunk at line %d", y);
	if (aim_encoder(enc, &ci, j) != 0)
		return -1;
	if (first && (rv = exr_encoding_choose_default_routines(ctx, 0, enc)) != EXR_ERR_SUCCESS)
		return fail_exr(j->k, rv, "choosing encoder");
	rv = exr_encoding_run(ctx, 0, enc);
	return rv == EXR_ERR_SUCCESS ? 0 : fail_exr(j->k, rv, "encoding chunk at line %d", y);
}

static int write_chunks(exr_context_t ctx, const wjob *j)
{
	int32_t lines = 0;
	exr_result_t rv = exr_get_scanlines_per_chunk(ctx, 0, &lines);
	if (rv != EXR_ERR_SUCCESS)
		return fail_exr(j->k, rv, "getting lines per chunk");
	if (lines < 1)
		return fail_msg(j->k, "%d lines per chunk", (int)lines);
	exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
	int bad = 0;
	/* the last chunk is shorter when height is not a multiple of lines; the chunk info
	 * says so and the library sizes that chunk from it */
	for (int y = 0; y < j->height && !bad; y += lines)
		bad = write_chunk(ctx, &enc, y, j) != 0;
	rv = exr_encoding_destroy(ctx, &enc);
	if (!bad && rv != EXR_ERR_SUCCESS)
		return fail_exr(j->k, rv, "releasing encoder");
	return bad ? -1 : 0;
}

/* Everything that goes through the library; exr_finish writes the offset table, so
 * its result counts too. */
static int write_exr(const char *path, wjob *j)
{
	exr_context_initializer_t init = ctx_init(&j->fd);
	init.write_fn = write_fd; /* with it, path only names the file in library messages */
	exr_context_t ctx = NULL;
	exr_result_t rv = exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init);
	if (rv != EXR_ERR_SUCCESS)
		return fail_exr(j->k, rv, "starting write");
	int bad = define_part(ctx, j) != 0 || write_chunks(ctx, j) != 0;
	rv = exr_finish(&ctx);
	if (!bad && rv != EXR_ERR_SUCCESS)
		return fail_exr(j->k, rv, "finishing file");
	return bad ? -1 : 0;
}

int bk_exr_write(const char *path, int width, int height, int nchan,
                 const char *const *names, const float *const *data, int half,
                 const bk_exr_attr *attrs, int nattrs, char *err, size_t errlen)
{
	sink k;
	sink_begin(&k, path, err, errlen);
	wjob j = {width, height, nchan, half, nattrs, names, data, attrs, -1, &k};
	int rc = -1;
	if (!path || !path[0])
		fail_msg(&k, "invalid argument: empty path");
	else if (check_args(&j) == 0) {
		bk_out o;
		char oerr[1024];
		if (bk_out_open(&o, path, oerr, sizeof oerr) != 0) {
			fail_out(&k, oerr);
		} else {
			j.fd = fileno(o.f);
			if (write_exr(path, &j) != 0)
				bk_out_abort(&o);
			else if ((rc = bk_out_commit(&o, oerr, sizeof oerr)) != 0) /* synced, renamed, its directory synced */
				fail_out(&k, oerr);
		}
	}
	cur_sink = NULL;
	return rc;
}

size_t bk_exr_nonfinite(const float *data, size_t n, int half)
{
	/* 65520 = 65504 + half an ulp (16): the least float HALF rounds to +inf */
	size_t bad = 0;
	for (size_t k = 0; k < n; k++)
		bad += !isfinite(data[k]) || (half && fabsf(data[k]) >= 65520.0f);
	return bad;
}

/* ---- read -------------------------------------------------------------------- */

void bk_exr_image_free(bk_exr_image *img)
{
	if (!img)
		return;
	for (int c = 0; c < 4; c++)
		free(img->data[c]);
	memset(img, 0, sizeof *img);
}

int bk_exr_channel_index(const bk_exr_image *img, const char *name)
{
	for (int c = 0; img && name && c < img->nchan; c++)
		if (strcmp(img->names[c], name) == 0)
			return c;
	return -1;
}

static int read_channels(exr_context_t ctx, bk_exr_image *img, sink *k)
{
	const exr_attr_chlist_t *cl = NULL;
	exr_result_t rv = exr_get_channels(ctx, 0, &cl);
	if (rv != EXR_ERR_SUCCESS || !cl)
		return fail_exr(k, rv, "reading channel list");
	if (cl->num_channels < 1 || cl->num_channels > 4)
		return fail_msg(k, "%d channels, expected 1 to 4", cl->num_channels);
	img->nchan = cl->num_channels;
	for (int c = 0; c < img->nchan; c++) {
		const exr_attr_chlist_entry_t *e = &cl->entries[c];
		if (e->pixel_type != EXR_PIXEL_HALF && e->pixel_type != EXR_PIXEL_FLOAT)
			return fail_msg(k, "channel '%s' is not half or float", e->name.str);
		if (e->x_sampling != 1 || e->y_sampling != 1)
			return fail_msg(k, "channel '%s' is subsampled", e->name.str);
		if (e->name.length < 1 || e->name.length > 31)
			return fail_msg(k, "channel name '%s' is not 1 to 31 bytes", e->name.str);
		memcpy(img->names[c], e->name.str, (size_t)e->name.length);
		img->names[c][e->name.length] = '\0';
		img->half[c] = e->pixel_type == EXR_PIXEL_HALF;
	}
	return 0;
}

/* Header facts the chunk loop needs: a scanline part, its size and its planes. */
static int read_layout(exr_context_t ctx, bk_exr_image *img, exr_attr_box2i_t *dw, sink *k)
{
	exr_storage_t st;
	exr_compression_t comp;
	exr_result_t rv = exr_get_storage(ctx, 0, &st);
	if (rv != EXR_ERR_SUCCESS)
		return fail_exr(k, rv, "reading storage type");
	if (st != EXR_STORAGE_SCANLINE)
		return fail_msg(k, "not a flat scanline image");
	if ((rv = exr_get_compression(ctx, 0, &comp)) != EXR_ERR_SUCCESS)
		return fail_exr(k, rv, "reading compression");
	img->compression = (int)comp;
	if ((rv = exr_get_data_window(ctx, 0, dw)) != EXR_ERR_SUCCESS)
		return fail_exr(k, rv, "reading data window");
	int64_t w = (int64_t)dw->max.x - dw->min.x + 1, h = (int64_t)dw->max.y - dw->min.y + 1;
	if (w < 1 || h < 1 || w > INT32_MAX || h > INT32_MAX ||
	    (uint64_t)w * (uint64_t)h > SIZE_MAX / sizeof(float))
		return fail_msg(k, "unusable data window %lldx%lld", (long long)w, (long long)h);
	img->width = (int)w;
	img->height = (int)h;
	if (read_channels(ctx, img, k) != 0)
		return -1;
	size_t n = (size_t)img->width * (size_t)img->height;
	for (int c = 0; c < img->nchan; c++)
		if (!(img->data[c] = malloc(n * sizeof(float))))
			return fail_msg(k, "out of memory for %dx%d image", img->width, img->height);
	return 0;
}

/* Decoder channels follow the channel list, which is the order of img->names. */
static void aim_decoder(exr_decode_pipeline_t *dec, const exr_chunk_info_t *ci,
                        const bk_exr_image *img, const exr_attr_box2i_t *dw)
{
	size_t row = (size_t)((int64_t)ci->start_y - dw->min.y);
	for (int c = 0; c < dec->channel_count; c++) {
		exr_coding_channel_info_t *ch = &dec->channels[c];
		ch->decode_to_ptr = (uint8_t *)(img->data[c] + row * (size_t)img->width);
		ch->user_pixel_stride = (int32_t)sizeof(float);
		ch->user_line_stride = (int32_t)sizeof(float) * img->width;
		ch->user_data_type = EXR_PIXEL_FLOAT; /* HALF channels: the library converts */
		ch->user_bytes_per_element = (int16_t)sizeof(float);
	}
}

static int read_chunk(exr_context_t ctx, exr_decode_pipeline_t *dec, int y, int first,
                      const bk_exr_image *img, const exr_attr_box2i_t *dw, sink *k)
{
	exr_chunk_info_t ci;
	exr_result_t rv = exr_read_scanline_chunk_info(ctx, 0, y, &ci);
	if (rv != EXR_ERR_SUCCESS)
		return fail_exr(k, rv, "chunk at line %d", y);
	rv = first ? exr_decoding_initialize(ctx, 0, &ci, dec) : exr_decoding_update(ctx, 0, &ci, dec);
	if (rv != EXR_ERR_SUCCESS)
		return fail_exr(k, rv, "preparing chunk at line %d", y);
	if (dec->channel_count != img->nchan)
		return fail_msg(k, "chunk at line %d has %d channels, header %d", y,
		                (int)dec->channel_count, img->nchan);
	aim_decoder(dec, &ci, img, dw);
	if (first && (rv = exr_decoding_choose_default_routines(ctx, 0, dec)) != EXR_ERR_SUCCESS)
		return fail_exr(k, rv, "choosing decoder");
	rv = exr_decoding_run(ctx, 0, dec);
	return rv == EXR_ERR_SUCCESS ? 0 : fail_exr(k, rv, "decoding chunk at line %d", y);
}

static int read_chunks(exr_context_t ctx, const bk_exr_image *img, const exr_attr_box2i_t *dw,
                       sink *k)
{
	int32_t lines = 0;
	exr_result_t rv = exr_get_scanlines_per_chunk(ctx, 0, &lines);
	if (rv != EXR_ERR_SUCCESS)
		return fail_exr(k, rv, "getting lines per chunk");
	if (lines < 1)
		return fail_msg(k, "%d lines per chunk", (int)lines);
	exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
	int bad = 0;
	/* chunks start at the data window's top; the last one may be shorter */
	for (int64_t y = dw->min.y; y <= dw->max.y && !bad; y += lines)
		bad = read_chunk(ctx, &dec, (int)y, y == dw->min.y, img, dw, k) != 0;
	rv = exr_decoding_destroy(ctx, &dec);
	if (!bad && rv != EXR_ERR_SUCCESS)
		return fail_exr(k, rv, "releasing decoder");
	return bad ? -1 : 0;
}

int bk_exr_read(const char *path, bk_exr_image *img, char *err, size_t errlen)
{
	sink k;
	sink_begin(&k, path, err, errlen);
	int rc = -1;
	if (!img) {
		fail_msg(&k, "invalid argument: no image");
	} else {
		memset(img, 0, sizeof *img);
		exr_context_initializer_t init = ctx_init(NULL);
		exr_context_t ctx = NULL;
		exr_result_t rv = exr_start_read(&ctx, path, &init);
		if (rv != EXR_ERR_SUCCESS) {
			fail_exr(&k, rv, "cannot open");
		} else {
			exr_attr_box2i_t dw;
			if (read_layout(ctx, img, &dw, &k) == 0 && read_chunks(ctx, img, &dw, &k) == 0)
				rc = 0;
			rv = exr_finish(&ctx);
			if (rc == 0 && rv != EXR_ERR_SUCCESS)
				rc = fail_exr(&k, rv, "closing");
		}
		if (rc != 0)
			bk_exr_image_free(img);
	}
	cur_sink = NULL;
	return rc;
}

/* ---- attributes ----------------------------------------------------------------- */

static int format_attr(const exr_attribute_t *a, char *buf, size_t len)
{
	int n;
	if (a->type == EXR_ATTR_STRING && a->string)
		n = snprintf(buf, len, "%.*s", (int)a->string->length, a->string->str);
	else if (a->type == EXR_ATTR_INT)
		n = snprintf(buf, len, "%d", (int)a->i);
	else
		return -1;
	/* a truncated value would pass for a real one */
	return n >= 0 && (size_t)n < len ? 0 : -1;
}

int bk_exr_read_attr(const char *path, const char *name, char *buf, size_t len)
{
	if (!path || !name || !buf || len == 0)
		return -1;
	buf[0] = '\0';
	/* no sink: a missing attribute is an answer, not an error, and must not print */
	cur_sink = NULL;
	exr_context_initializer_t init = ctx_init(NULL);
	init.flags |= EXR_CONTEXT_FLAG_SILENT_HEADER_PARSE;
	exr_context_t ctx = NULL;
	if (exr_start_read(&ctx, path, &init) != EXR_ERR_SUCCESS)
		return -1;
	const exr_attribute_t *a = NULL;
	int rc = -1;
	if (exr_get_attribute_by_name(ctx, 0, name, &a) == EXR_ERR_SUCCESS && a)
		rc = format_attr(a, buf, len);
	if (exr_finish(&ctx) != EXR_ERR_SUCCESS)
		rc = -1;
	if (rc != 0)
		buf[0] = '\0';
	return rc;
}
