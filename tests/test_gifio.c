/* test_gifio.c: the animated GIF writer (src/io/gifio.c) read back with
 * giflib: the frames, their size, the loop, the colours each frame shows
 * (through its own map), and refusals (frames of two sizes, none). */
#include "tests/tt.h"

#include "src/io/io.h"

#include <gif_lib.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const uint8_t col[3][3] = {{200, 40, 30}, {20, 150, 60}, {30, 60, 220}};

/* Frame k: its colour on the left half, white on the right. */
static td_image *frame(int k, int w, int h)
{
    td_image *im = td_image_new(w, h, 3, NULL);
    int x, y, c;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++)
            for (c = 0; c < 3; c++)
                im->data[(size_t)y * im->stride + 3 * (size_t)x + c] =
                    x < w / 2 ? col[k][c] : 255;
    return im;
}

static void test_gif_roundtrip(void)
{
    char path[] = "/tmp/tdgifXXXXXX";
    td_image *fr[3];
    GifFileType *g;
    int fd = mkstemp(path), err = 0, k, c, loops = 0, e;
    TT_CHECK(fd >= 0);
    close(fd);
    for (k = 0; k < 3; k++)
        fr[k] = frame(k, 40, 20);
    TT_CHECK(td_gif_write(path, fr, 3, 10, NULL) == 0);
    g = DGifOpenFileName(path, &err);
    TT_CHECK(g != NULL);
    if (g) {
        TT_CHECK(DGifSlurp(g) == GIF_OK);
        TT_CHECKF(g->ImageCount == 3 && g->SWidth == 40 && g->SHeight == 20,
                  "%d frames of %d x %d", g->ImageCount, g->SWidth, g->SHeight);
        for (k = 0; k < g->ImageCount && k < 3; k++) {
            const SavedImage *im = &g->SavedImages[k];
            const ColorMapObject *m = im->ImageDesc.ColorMap
                                          ? im->ImageDesc.ColorMap
                                          : g->SColorMap;
            GifColorType a = m->Colors[im->RasterBits[5 * 40 + 3]];
            GifColorType b = m->Colors[im->RasterBits[5 * 40 + 35]];
            /* median cut keeps 5 bits a channel: within 8 */
            int d = abs(a.Red - col[k][0]) > 8 || abs(a.Green - col[k][1]) > 8 ||
                    abs(a.Blue - col[k][2]) > 8;
            TT_CHECKF(!d && b.Red > 240 && b.Green > 240 && b.Blue > 240,
                      "frame %d: %d %d %d, want %d %d %d", k, a.Red, a.Green,
                      a.Blue, col[k][0], col[k][1], col[k][2]);
            for (e = 0; e < im->ExtensionBlockCount; e++)
                if (im->ExtensionBlocks[e].Function == GRAPHICS_EXT_FUNC_CODE) {
                    GraphicsControlBlock gcb;
                    DGifExtensionToGCB(im->ExtensionBlocks[e].ByteCount,
                                       im->ExtensionBlocks[e].Bytes, &gcb);
                    TT_CHECK(gcb.DelayTime == 10);
                }
        }
        for (k = 0; k < g->ImageCount; k++) /* NETSCAPE2.0: the loop */
            for (e = 0; e < g->SavedImages[k].ExtensionBlockCount; e++) {
                const ExtensionBlock *x = &g->SavedImages[k].ExtensionBlocks[e];
                loops += x->Function == APPLICATION_EXT_FUNC_CODE &&
                         x->ByteCount == 11 && !memcmp(x->Bytes, "NETSCAPE2.0", 11);
            }
        TT_CHECK(loops == 1);
        DGifCloseFile(g, &err);
    }
    for (c = 0; c < 3; c++)
        td_image_free(fr[c]);
    unlink(path);
}

static void test_gif_refused(void)
{
    char path[] = "/tmp/tdgifXXXXXX";
    td_image *fr[2] = {frame(0, 40, 20), frame(1, 30, 20)};
    td_ctx cx;
    int fd = mkstemp(path);
    td_ctx_init(&cx);
    TT_CHECK(fd >= 0);
    close(fd);
    unlink(path);
    TT_CHECK(td_gif_write(path, fr, 2, 10, &cx) == TD_EIO);
    TT_CHECK(access(path, F_OK) != 0); /* nothing left behind */
    TT_CHECK(td_gif_write(path, fr, 0, 10, NULL) == TD_EINVAL);
    td_image_free(fr[0]), td_image_free(fr[1]);
}

int main(void)
{
    TT_RUN(test_gif_roundtrip);
    TT_RUN(test_gif_refused);
    return tt_summary();
}
