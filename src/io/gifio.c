/* gifio.c: animated GIF (giflib): frames of one size, each quantised to
 * its own 256-colour map (median cut, GifQuantizeBuffer), looping, written
 * to a temporary file and renamed. */
#include "src/io/io.h"

#include <gif_lib.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int put(GifFileType *g, const GifByteType *b, int n)
{
    return (int)fwrite(b, 1, (size_t)n, (FILE *)g->UserData);
}

/* One frame: its colours quantised, a graphics control block (delay), the
 * image with a local map. */
static int frame(GifFileType *g, const td_image *im, int delay_cs)
{
    size_t n = (size_t)im->w * im->h, i;
    GifByteType *r = malloc(n), *gr = malloc(n), *b = malloc(n),
                *out = malloc(n);
    ColorMapObject *map = GifMakeMapObject(256, NULL);
    GraphicsControlBlock gcb;
    GifByteType ext[4];
    int size = 256, rc = -1, y;
    if (!r || !gr || !b || !out || !map)
        goto done;
    for (i = 0; i < n; i++) {
        const uint8_t *p = im->data + (i / im->w) * im->stride +
                           (i % im->w) * (size_t)im->channels;
        r[i] = p[0];
        gr[i] = im->channels >= 3 ? p[1] : p[0];
        b[i] = im->channels >= 3 ? p[2] : p[0];
    }
    if (GifQuantizeBuffer((unsigned)im->w, (unsigned)im->h, &size, r, gr, b,
                          out, map->Colors) == GIF_ERROR)
        goto done;
    memset(&gcb, 0, sizeof gcb);
    gcb.DelayTime = delay_cs, gcb.TransparentColor = NO_TRANSPARENT_COLOR;
    EGifGCBToExtension(&gcb, ext);
    if (EGifPutExtension(g, GRAPHICS_EXT_FUNC_CODE, 4, ext) == GIF_ERROR ||
        EGifPutImageDesc(g, 0, 0, im->w, im->h, false, map) == GIF_ERROR)
        goto done;
    for (y = 0; y < im->h; y++)
        if (EGifPutLine(g, out + (size_t)y * im->w, im->w) == GIF_ERROR)
            goto done;
    rc = 0;
done:
    GifFreeMapObject(map);
    free(r), free(gr), free(b), free(out);
    return rc;
}

/* See io.h. */
int td_gif_write(const char *path, td_image *const *frames, size_t n,
                 int delay_cs, td_ctx *cx)
{
    char tmp[4096];
    FILE *f;
    GifFileType *g;
    int err = 0, rc = 0;
    size_t k;
    static const GifByteType loop[3] = {1, 0, 0}; /* loop for ever */
    if (n == 0 || frames[0]->w < 1 || frames[0]->h < 1 ||
        frames[0]->w > 65535 || frames[0]->h > 65535)
        return td_seterr(cx, TD_EINVAL, "%s: no frames, or frames too large "
                         "for a GIF", path);
    if (!(f = td_atomic_open(path, tmp, sizeof tmp, cx)))
        return cx && cx->code ? cx->code : TD_EIO;
    if (!(g = EGifOpen(f, put, &err))) {
        td_atomic_abort(f, tmp);
        return td_seterr(cx, TD_EIO, "%s: %s", path, GifErrorString(err));
    }
    EGifSetGifVersion(g, true);
    if (EGifPutScreenDesc(g, frames[0]->w, frames[0]->h, 8, 0, NULL) ==
            GIF_ERROR ||
        EGifPutExtensionLeader(g, APPLICATION_EXT_FUNC_CODE) == GIF_ERROR ||
        EGifPutExtensionBlock(g, 11, "NETSCAPE2.0") == GIF_ERROR ||
        EGifPutExtensionBlock(g, 3, loop) == GIF_ERROR ||
        EGifPutExtensionTrailer(g) == GIF_ERROR)
        rc = -1;
    for (k = 0; k < n && rc == 0; k++)
        if (frames[k]->w != frames[0]->w || frames[k]->h != frames[0]->h ||
            frame(g, frames[k], delay_cs) != 0)
            rc = -1;
    if (EGifCloseFile(g, &err) == GIF_ERROR)
        rc = -1;
    if (rc != 0) {
        td_atomic_abort(f, tmp);
        return td_seterr(cx, TD_EIO, "%s: writing the GIF failed", path);
    }
    return td_atomic_commit(f, tmp, path, cx);
}
