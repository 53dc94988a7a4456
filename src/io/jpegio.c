/* jpegio.c: JPEG scans through libjpeg(-turbo), straight into a td_image.
 *
 * OpenCV's decoder (the shim's td_cv_read_jpeg) lets libjpeg print its
 * warnings ("Corrupt JPEG data", "Premature end of JPEG file") to stderr
 * and returns the damaged image as if it were whole.  Here every warning
 * is an error naming the file: a scan that is cut short or corrupt is
 * refused, never traced with a grey band where its data ends.  The frame
 * is checked against the file's size before any pixel memory is taken (a
 * baseline JPEG needs about 2 bits per 8 x 8 block; under 1/4 bit per
 * block the header lies). */
#include "src/io/io_int.h"

#include <errno.h>
#include <setjmp.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include <jpeglib.h>

typedef struct jerr {
    struct jpeg_error_mgr mgr;
    jmp_buf jump;
    char msg[JMSG_LENGTH_MAX];
} jerr;

static void on_error(j_common_ptr ci)
{
    jerr *e = (jerr *)ci->err;
    (*ci->err->format_message)(ci, e->msg);
    longjmp(e->jump, 1);
}

/* Warnings (level -1) are corrupt data: fail as on an error. */
static void on_message(j_common_ptr ci, int level)
{
    if (level < 0)
        on_error(ci);
}

int td_jpeg_read(const char *path, td_image **out, td_ctx *cx)
{
    struct jpeg_decompress_struct ci;
    jerr e;
    FILE *f;
    td_image *volatile im = NULL;
    struct stat st;
    int rc = 0;
    if (!(f = fopen(path, "rb")))
        return td_seterr(cx, TD_EIO, "%s: cannot open: %s", path,
                         strerror(errno));
    memset(&ci, 0, sizeof ci);
    ci.err = jpeg_std_error(&e.mgr);
    e.mgr.error_exit = on_error;
    e.mgr.emit_message = on_message;
    e.msg[0] = '\0';
    if (setjmp(e.jump)) {
        rc = td_seterr(cx, TD_EFORMAT, "%s: cannot decode JPEG (%s)", path,
                       e.msg[0] ? e.msg : "corrupt");
        goto done;
    }
    jpeg_create_decompress(&ci);
    jpeg_stdio_src(&ci, f);
    jpeg_read_header(&ci, TRUE);
    if ((rc = td_check_dims((long)ci.image_width, (long)ci.image_height,
                            path, cx)) != 0)
        goto done;
    if (fstat(fileno(f), &st) == 0 &&
        (double)st.st_size <
            (double)ci.image_width * (double)ci.image_height / 2048.0) {
        rc = td_seterr(cx, TD_EFORMAT,
                       "%s: cannot decode JPEG (%u x %u pixels claimed in "
                       "only %lld bytes: truncated or corrupt)",
                       path, ci.image_width, ci.image_height,
                       (long long)st.st_size);
        goto done;
    }
    ci.out_color_space = ci.num_components == 1 ? JCS_GRAYSCALE : JCS_RGB;
    jpeg_start_decompress(&ci);
    if ((ci.output_components != 1 && ci.output_components != 3) ||
        !(im = td_image_new((int)ci.output_width, (int)ci.output_height,
                            ci.output_components, cx))) {
        rc = cx && cx->code ? cx->code
                            : td_seterr(cx, TD_EFORMAT,
                                        "%s: cannot decode JPEG", path);
        goto done;
    }
    while (ci.output_scanline < ci.output_height) {
        JSAMPROW row = im->data + (size_t)ci.output_scanline * im->stride;
        jpeg_read_scanlines(&ci, &row, 1);
    }
    jpeg_finish_decompress(&ci);
done:
    jpeg_destroy_decompress(&ci);
    fclose(f);
    if (rc != 0) {
        td_image_free(im);
        return rc;
    }
    *out = im;
    return 0;
}
