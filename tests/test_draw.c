/* The traced-lines overlay (src/draw.c): lines drawn where they are, each
 * in its own colour, open ends marked, the scan faded behind. */
#include "tests/tt.h"
#include "src/core/core.h"

#include <string.h>

static const uint8_t *px(const td_image *im, int x, int y)
{
    return im->data + (size_t)y * im->stride + (size_t)x * 3;
}

static void test_overlay(void)
{
    td_image *scan = td_image_new(40, 30, 1, NULL), *ov = NULL;
    td_lines *ls = td_lines_new(NULL);
    td_line *a, *b;
    int x;
    memset(scan->data, 0, scan->stride * (size_t)scan->h); /* black scan */
    a = td_lines_add(ls, NULL);
    for (x = 5; x <= 30; x++)
        td_line_push(a, x + 0.5, 10.5, NULL); /* open, ends inside */
    b = td_lines_add(ls, NULL);
    td_line_push(b, 5.5, 20.5, NULL);
    td_line_push(b, 15.5, 20.5, NULL);
    td_line_push(b, 15.5, 25.5, NULL);
    b->closed = 1; /* the closing segment runs back to (5,20) */
    TT_CHECK(td_draw_overlay(scan, ls, &ov, NULL) == 0);
    TT_CHECK(ov && ov->w == 40 && ov->h == 30 && ov->channels == 3);
    /* faded scan: black becomes 60 % grey */
    TT_CHECK(px(ov, 0, 0)[0] == 153 && px(ov, 0, 0)[2] == 153);
    /* the open line's middle is drawn in colour 0, not grey */
    {
        uint8_t c0[3], c1[3];
        td_draw_colour(0, c0);
        td_draw_colour(1, c1);
        TT_CHECK(memcmp(px(ov, 18, 10), c0, 3) == 0);
        TT_CHECK(memcmp(c0, c1, 3) != 0);
        TT_CHECK(memcmp(px(ov, 10, 22), c1, 3) == 0); /* closing diagonal */
    }
    /* the open ends get a red box around them */
    TT_CHECK(px(ov, 4, 9)[0] == 230 && px(ov, 4, 9)[1] == 0);
    TT_CHECK(px(ov, 31, 11)[0] == 230 && px(ov, 31, 11)[1] == 0);
    td_image_free(ov);
    td_image_free(scan);
    td_lines_free(ls);
}

int main(void)
{
    TT_RUN(test_overlay);
    return tt_summary();
}
