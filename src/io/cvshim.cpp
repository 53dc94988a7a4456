// cvshim.cpp: the OpenCV shim (the project's only C++ file).
//
// Every extern "C" entry point runs its body inside guarded(), which
// catches cv::Exception, std::bad_alloc and anything else and turns them
// into a TD_E* code with a message in the caller's td_ctx.  No C++ type
// crosses cvshim.h.  Grids and images are wrapped in cv::Mat headers over
// their own memory wherever OpenCV allows, so nothing is copied needlessly.
#include "src/io/io.h"

#include <climits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <thread>
#include <vector>

#include <dlfcn.h>
#include <unistd.h>

namespace
{

const int BAND = 128; // rows per band for the banded filters

// Run body(); any C++ exception becomes a TD_E* code with a message naming
// `what`.  Returns body's own result otherwise.
template <class F> int guarded(const char *what, td_ctx *cx, F &&body)
{
    try {
        return body();
    } catch (const cv::Exception &e) {
        int code = e.code == cv::Error::StsNoMem ? TD_ENOMEM : TD_EINTERNAL;
        return td_seterr(cx, code, "%s: OpenCV: %s", what, e.err.c_str());
    } catch (const std::bad_alloc &) {
        return td_seterr(cx, TD_ENOMEM, "%s: out of memory", what);
    } catch (...) {
        return td_seterr(cx, TD_EINTERNAL, "%s: unexpected C++ exception",
                         what);
    }
}

cv::Mat wrap_grid(const td_grid_u8 *g)
{
    return cv::Mat(g->h, g->w, CV_8UC1, g->data, g->stride);
}

int check_grid(const td_grid_u8 *g, const char *what, td_ctx *cx)
{
    if (!g || !g->data || g->w <= 0 || g->h <= 0 || g->stride < (size_t)g->w)
        return td_seterr(cx, TD_EINVAL, "%s: invalid grid", what);
    return 0;
}

int same_size(const td_grid_u8 *a, int w, int h, const char *what, td_ctx *cx)
{
    if (a->w != w || a->h != h)
        return td_seterr(cx, TD_EINVAL, "%s: output is %d x %d, input %d x %d",
                         what, a->w, a->h, w, h);
    return 0;
}

// ---- JPEG --------------------------------------------------------------

// Read a whole file.  0, or TD_EIO with the message set.
int slurp(const char *path, std::vector<uchar> &buf, td_ctx *cx)
{
    FILE *f = std::fopen(path, "rb");
    if (!f)
        return td_seterr(cx, TD_EIO, "%s: cannot open: %s", path,
                         std::strerror(errno));
    uchar chunk[65536];
    size_t n;
    while ((n = std::fread(chunk, 1, sizeof chunk, f)) > 0)
        buf.insert(buf.end(), chunk, chunk + n);
    int bad = std::ferror(f);
    std::fclose(f);
    if (bad)
        return td_seterr(cx, TD_EIO, "%s: read error", path);
    return 0;
}

// Find the JPEG frame header (SOFn) and return its size and component
// count: 0, or -1 when the stream is not a JPEG or ends before a frame.
//   FFD8 | FFxx len(2) payload(len-2) | ... | FFCn len P Y(2) X(2) Nf ...
int jpeg_frame(const uchar *p, size_t n, int *w, int *h, int *nc)
{
    if (n < 4 || p[0] != 0xFF || p[1] != 0xD8)
        return -1;
    size_t i = 2;
    while (i + 4 <= n) {
        if (p[i] != 0xFF)
            return -1;
        unsigned m = p[i + 1];
        if (m == 0xFF) { // fill byte
            i++;
            continue;
        }
        i += 2;
        if (m == 0x01 || (m >= 0xD0 && m <= 0xD8))
            continue; // markers without a payload
        if (m == 0xD9 || m == 0xDA)
            return -1; // end of image or scan before any frame header
        size_t len = ((size_t)p[i] << 8) | p[i + 1];
        if (len < 2 || i + len > n)
            return -1;
        if (m >= 0xC0 && m <= 0xCF && m != 0xC4 && m != 0xC8 && m != 0xCC) {
            if (len < 8)
                return -1;
            *h = (p[i + 3] << 8) | p[i + 4];
            *w = (p[i + 5] << 8) | p[i + 6];
            *nc = p[i + 7];
            return 0;
        }
        i += len;
    }
    return -1;
}

// Whether an end-of-image marker (FFD9) follows the first start-of-scan
// (FFDA) segment.  Entropy-coded data stuffs every FF byte as FF00, so
// FFD9 there is the marker; a file cut short has none, and libjpeg would
// silently pad the missing rows with grey.
bool jpeg_has_eoi(const uchar *p, size_t n)
{
    size_t i = 2;
    while (i + 4 <= n && p[i] == 0xFF) { // walk the segments up to SOS
        unsigned m = p[i + 1];
        if (m == 0xFF || m == 0x01 || (m >= 0xD0 && m <= 0xD8)) {
            i += m == 0xFF ? 1 : 2;
            continue;
        }
        size_t len = ((size_t)p[i + 2] << 8) | p[i + 3];
        i += 2 + len;
        if (m == 0xDA)
            break;
    }
    for (; i + 1 < n; i++)
        if (p[i] == 0xFF && p[i + 1] == 0xD9)
            return true;
    return false;
}

// Swap R and B of every pixel in place (OpenCV decodes to BGR).
void swap_rb(td_image *im)
{
    for (int y = 0; y < im->h; y++) {
        uint8_t *p = im->data + (size_t)y * im->stride;
        for (int x = 0; x < im->w; x++, p += 3)
            std::swap(p[0], p[2]);
    }
}

int read_jpeg(const char *path, td_image **out, td_ctx *cx)
{
    std::vector<uchar> buf;
    int w = 0, h = 0, nc = 0, rc = slurp(path, buf, cx);
    if (rc != 0)
        return rc;
    if (jpeg_frame(buf.data(), buf.size(), &w, &h, &nc) != 0 ||
        (nc != 1 && nc != 3 && nc != 4))
        return td_seterr(cx, TD_EFORMAT, "%s: cannot decode JPEG", path);
    if (!jpeg_has_eoi(buf.data(), buf.size()))
        return td_seterr(cx, TD_EFORMAT,
                         "%s: cannot decode JPEG (truncated: no end marker)",
                         path);
    std::string what = std::string("JPEG '") + path + "'";
    if ((rc = td_check_dims(w, h, what.c_str(), cx)) != 0)
        return rc;
    // Every 8 x 8 block of a baseline JPEG takes at least about 2 bits
    // (a blank sheet: 62660 bytes for 4000 x 4000); a file far smaller
    // than its frame claims is cut short or forged, and decoding it would
    // allocate the whole frame first.  A quarter of a bit per block leaves
    // room for arithmetic coding.
    if ((double)buf.size() < (double)w * (double)h / 2048.0)
        return td_seterr(cx, TD_EFORMAT,
                         "%s: cannot decode JPEG (%d x %d pixels claimed in "
                         "only %zu bytes: truncated or corrupt)",
                         path, w, h, buf.size());
    if ((size_t)w * (size_t)h > ((size_t)1 << 30) &&
        !std::getenv("CV_IO_MAX_IMAGE_PIXELS"))
        return td_seterr(cx, TD_ETOOBIG,
                         "%s: %d x %d pixels is over OpenCV's JPEG limit of "
                         "2^30 (set CV_IO_MAX_IMAGE_PIXELS to raise it)",
                         path, w, h);
    int ch = nc == 1 ? 1 : 3;
    // Freed on every early return and on an exception from imdecode.
    std::unique_ptr<td_image, void (*)(td_image *)> im(
        td_image_new(w, h, ch, cx), td_image_free);
    if (!im)
        return TD_ENOMEM;
    cv::Mat dst(h, w, CV_8UC(ch), im->data, im->stride);
    int flags = (ch == 1 ? cv::IMREAD_GRAYSCALE : cv::IMREAD_COLOR) |
                cv::IMREAD_IGNORE_ORIENTATION;
    cv::imdecode(buf, flags, &dst);
    buf.clear();
    buf.shrink_to_fit();
    if (dst.empty() || dst.rows != h || dst.cols != w ||
        dst.type() != CV_8UC(ch))
        return td_seterr(cx, TD_EFORMAT, "%s: cannot decode JPEG", path);
    if (dst.data != im->data) // OpenCV chose its own buffer: copy over
        dst.copyTo(cv::Mat(h, w, CV_8UC(ch), im->data, im->stride));
    if (ch == 3)
        swap_rb(im.get());
    *out = im.release();
    return 0;
}

int write_file_atomic(const char *path, const std::vector<uchar> &bytes,
                      td_ctx *cx)
{
    char tmp[4096];
    FILE *f = td_atomic_open(path, tmp, sizeof tmp, cx);
    if (!f)
        return cx ? cx->code : TD_EIO;
    if (std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size()) {
        int e = errno;
        td_atomic_abort(f, tmp);
        return td_seterr(cx, TD_EIO, "%s: cannot write: %s", path,
                         std::strerror(e));
    }
    return td_atomic_commit(f, tmp, path, cx);
}

// ---- banded filters ----------------------------------------------------

// A private copy of the input rows [top, bot) of a grid.  Loading a later
// range keeps the rows it shares with the current one, so callers may
// write output rows < top over the input.
class band_ring
{
  public:
    band_ring(const td_grid_u8 *g, int halo)
        : g_(g), buf_((size_t)(BAND + 2 * halo) * (size_t)g->w)
    {
    }
    // Make rows [a, b) available; a must not decrease between calls.
    void load(int a, int b)
    {
        size_t w = (size_t)g_->w;
        int from = a;
        if (a < bot_) {
            std::memmove(buf_.data(), buf_.data() + (size_t)(a - top_) * w,
                         (size_t)(bot_ - a) * w);
            from = bot_;
        }
        for (int y = from; y < b; y++)
            std::memcpy(buf_.data() + (size_t)(y - a) * w,
                        g_->data + (size_t)y * g_->stride, w);
        top_ = a;
        bot_ = b;
    }
    // A header over exactly the loaded rows (so OpenCV's ROI-aware
    // borders see these rows as the whole image).
    cv::Mat rows()
    {
        return cv::Mat(bot_ - top_, g_->w, CV_8UC1, buf_.data(), (size_t)g_->w);
    }
    int top() const
    {
        return top_;
    }

  private:
    const td_grid_u8 *g_;
    std::vector<uchar> buf_;
    int top_ = 0, bot_ = 0;
};

// Sauvola on one band: s rows (a header into the ring) -> mask rows.
void sauvola_rows(const cv::Mat &s, const cv::Mat &mean, const cv::Mat &sq,
                  double k, td_grid_u8 *mask, int y0)
{
    const float kf = (float)k;
    for (int r = 0; r < s.rows; r++) {
        const uchar *sp = s.ptr<uchar>(r);
        const float *mp = mean.ptr<float>(r), *qp = sq.ptr<float>(r);
        uint8_t *out = mask->data + (size_t)(y0 + r) * mask->stride;
        for (int x = 0; x < s.cols; x++) {
            float m = mp[x], var = qp[x] - m * m;
            float sd = var > 0.f ? std::sqrt(var) : 0.f;
            float t = 255.f - (255.f - m) * (1.f + kf * (sd / 128.f - 1.f));
            out[x] = (float)sp[x] > t;
        }
    }
}

int sauvola(const td_grid_u8 *s, int window, double k, td_grid_u8 *mask,
            td_ctx *cx)
{
    int r = window / 2, w = s->w, h = s->h;
    band_ring ring(s, r);
    cv::Mat mean(BAND, w, CV_32F), sq(BAND, w, CV_32F);
    cv::Size ks(window, window);
    for (int y0 = 0; y0 < h; y0 += BAND) {
        int y1 = std::min(h, y0 + BAND), n = y1 - y0;
        int a = std::max(0, y0 - r), b = std::min(h, y1 + r);
        ring.load(a, b);
        cv::Mat roi = ring.rows().rowRange(y0 - a, y1 - a);
        cv::Mat m = mean.rowRange(0, n), q = sq.rowRange(0, n);
        cv::boxFilter(roi, m, CV_32F, ks, cv::Point(-1, -1), true,
                      cv::BORDER_REFLECT_101);
        cv::sqrBoxFilter(roi, q, CV_32F, ks, cv::Point(-1, -1), true,
                         cv::BORDER_REFLECT_101);
        sauvola_rows(roi, m, q, k, mask, y0);
        int rc = td_progress(cx, "sauvola", (double)y1 / h);
        if (rc != 0)
            return rc;
    }
    return 0;
}

int median3(td_grid_u8 *g, td_ctx *cx)
{
    int w = g->w, h = g->h;
    band_ring ring(g, 1);
    cv::Mat out(BAND + 2, w, CV_8UC1);
    for (int y0 = 0; y0 < h; y0 += BAND) {
        int y1 = std::min(h, y0 + BAND);
        int a = std::max(0, y0 - 1), b = std::min(h, y1 + 1);
        ring.load(a, b);
        cv::Mat o = out.rowRange(0, b - a);
        cv::medianBlur(ring.rows(), o, 3);
        for (int y = y0; y < y1; y++)
            std::memcpy(g->data + (size_t)y * g->stride, o.ptr(y - a),
                        (size_t)w);
        int rc = td_progress(cx, "median3", (double)y1 / h);
        if (rc != 0)
            return rc;
    }
    return 0;
}

// ---- speck removal and hole filling -------------------------------------

// Both run in bands of SPECK_BAND rows on threads: a component that a
// band holds whole is decided there as on the whole sheet; one that
// reaches the band's first or last row (and so may go on into the next
// band) and proved small there is decided afterwards, on one thread, by a
// fill over the whole sheet from within min_area rows of each boundary
// between bands (a component of fewer than min_area cells spans fewer
// rows).  The result is the serial one's on any thread count
// (tests/test_cvshim.c).  10000 x 10000 benchmark sheet, two threads:
// specks 0.19 -> 0.10 s, holes 0.17 -> 0.10 s.
const int SPECK_BAND = 256;

// Bounded 4-connected fill of the paper component of (x0,y0) within rows
// [b0, b1): returns 1 and makes it ink when it has fewer than min_area
// cells and touches neither the sheet border nor rows outside the band,
// else leaves it paper.  Cells are marked 2 while
// visited.
//   4-neighbourhood:     N
//                      W * E
//                        S
int fill_hole(td_grid_u8 *m, int x0, int y0, int min_area, int b0, int b1,
              std::vector<std::pair<int, int>> &list)
{
    static const int dx[4] = {1, 0, -1, 0}, dy[4] = {0, -1, 0, 1};
    bool small = true;
    list.clear();
    list.push_back({x0, y0});
    TD_AT(m, x0, y0) = 2;
    for (size_t i = 0; i < list.size() && small; i++)
        for (int k = 0; k < 4 && small; k++) {
            int x = list[i].first + dx[k], y = list[i].second + dy[k];
            if (x < 0 || y < b0 || x >= m->w || y >= b1)
                small = false; // the border (not a hole) or another band
            else if (TD_AT(m, x, y) == 0) {
                if ((int)list.size() + 1 >= min_area)
                    small = false;
                TD_AT(m, x, y) = 2;
                list.push_back({x, y});
            }
        }
    for (const auto &c : list)
        TD_AT(m, c.first, c.second) = small ? 1 : 0;
    return small;
}

// Holes in rows [y0, y1) seeded there, filled within rows [b0, b1): the
// first cell of a 4-connected paper component in raster order has ink
// above and to its left, so only those cells seed a fill.
size_t holes_rows(td_grid_u8 *m, int min_area, int y0, int y1, int b0, int b1,
                  std::vector<std::pair<int, int>> &list)
{
    size_t n = 0;
    for (int y = std::max(y0, std::max(b0 + 1, 1)); y < y1; y++) {
        uint8_t *row = m->data + (size_t)y * m->stride;
        const uint8_t *up = row - m->stride;
        for (int x = 1; x < m->w; x++) {
            if ((x & 7) == 1 && x + 8 <= m->w) { // skip paper 8 at a time
                uint64_t v;
                std::memcpy(&v, row + x - 1, 8);
                if (v == 0) {
                    x += 7;
                    continue;
                }
            }
            if (row[x] == 0 && row[x - 1] && up[x])
                n += (size_t)fill_hole(m, x, y, min_area, b0, b1, list);
        }
    }
    return n;
}

// fn(b0, b1) for the bands of SPECK_BAND rows of h on threads: the sum of
// what it returns (an exception inside a band is rethrown as bad_alloc).
template <class F> size_t on_bands(int h, F fn)
{
    int nb = (h + SPECK_BAND - 1) / SPECK_BAND;
    size_t n = 0;
    bool oom = false;
#pragma omp parallel for schedule(dynamic) reduction(+ : n)
    for (int b = 0; b < nb; b++) {
        try {
            n += fn(b * SPECK_BAND, std::min(h, (b + 1) * SPECK_BAND));
        } catch (...) {
#pragma omp atomic write
            oom = true;
        }
    }
    if (oom)
        throw std::bad_alloc();
    return n;
}

int fill_holes(td_grid_u8 *m, int min_area, size_t *filled, td_ctx *cx)
{
    int nb = (m->h + SPECK_BAND - 1) / SPECK_BAND;
    size_t n = on_bands(m->h, [&](int b0, int b1) {
        std::vector<std::pair<int, int>> band;
        return holes_rows(m, min_area, b0, b1, b0, b1, band);
    });
    std::vector<std::pair<int, int>> list;
    for (int b = 1; b < nb; b++) // about each boundary, the whole sheet
        n += holes_rows(m, min_area, std::max(0, b * SPECK_BAND - min_area),
                        std::min(m->h, b * SPECK_BAND + min_area), 0, m->h,
                        list);
    if (filled)
        *filled = n;
    return td_progress(cx, "holes", 1.0);
}

// Cell states during speck removal.
enum : uint8_t { PAPER = 0, INK = 1, BIG = 2, SEEN = 3, UNSURE = 4 };

struct xy {
    int x, y;
};

// Flood-fill the component of INK (or UNSURE) cell (x0,y0) within rows
// [b0, b1) until it proves large (min_area cells, or touches a BIG cell)
// or is exhausted.  Visited cells become BIG when large; when small,
// PAPER, or UNSURE when it met ink outside the band (rows b0 - 1 and b1
// are not read: another thread's).  Returns 1 when removed.
//   8-neighbourhood:  NW N NE
//                     W  *  E
//                     SW S SE
int fill_one(td_grid_u8 *m, int x0, int y0, int min_area, int b0, int b1,
             std::vector<xy> &list)
{
    list.clear();
    list.push_back({x0, y0});
    TD_AT(m, x0, y0) = SEEN;
    bool big = (size_t)min_area <= 1, edge = false;
    for (size_t i = 0; i < list.size() && !big; i++) {
        xy c = list[i];
        for (int dy = -1; dy <= 1 && !big; dy++) {
            int y = c.y + dy;
            if (y < 0 || y >= m->h)
                continue;
            if (y < b0 || y >= b1) {
                edge = true;
                continue;
            }
            uint8_t *row = m->data + (size_t)y * m->stride;
            for (int dx = -1; dx <= 1; dx++) {
                int x = c.x + dx;
                if (x < 0 || x >= m->w || row[x] == PAPER || row[x] == SEEN)
                    continue;
                if (row[x] == BIG || list.size() + 1 >= (size_t)min_area) {
                    big = true;
                    break;
                }
                row[x] = SEEN;
                list.push_back({x, y});
            }
        }
    }
    uint8_t v = big ? BIG : edge ? UNSURE : PAPER;
    for (const xy &c : list)
        TD_AT(m, c.x, c.y) = v;
    return !big && !edge;
}

// Whether an already-scanned 8-neighbour (W, NW, N, NE) of cell x is BIG.
inline bool touches_big(const uint8_t *row, const uint8_t *up, int x, int w)
{
    if (x > 0 && row[x - 1] == BIG)
        return true;
    if (!up)
        return false;
    return up[x] == BIG || (x > 0 && up[x - 1] == BIG) ||
           (x + 1 < w && up[x + 1] == BIG);
}

// The specks among rows [b0, b1), filled within them.
size_t specks_rows(td_grid_u8 *m, int min_area, int b0, int b1,
                   std::vector<xy> &list)
{
    size_t n = 0;
    for (int y = b0; y < b1; y++) {
        uint8_t *row = m->data + (size_t)y * m->stride;
        for (int x = 0; x < m->w; x++)
            row[x] = row[x] != 0;
    }
    for (int y = b0; y < b1; y++) {
        uint8_t *row = m->data + (size_t)y * m->stride;
        const uint8_t *up = y > b0 ? row - m->stride : nullptr;
        for (int x = 0; x < m->w; x++) {
            if (row[x] != INK) { // skip paper fast
                const void *q = std::memchr(row + x, INK, (size_t)(m->w - x));
                if (!q)
                    break;
                x = (int)((const uint8_t *)q - row);
            }
            if (touches_big(row, up, x, m->w)) // most cells of long lines
                row[x] = BIG;
            else
                n += (size_t)fill_one(m, x, y, min_area, b0, b1, list);
        }
    }
    return n;
}

int remove_specks(td_grid_u8 *m, int min_area, size_t *removed, td_ctx *cx)
{
    int nb = (m->h + SPECK_BAND - 1) / SPECK_BAND;
    size_t n = on_bands(m->h, [&](int b0, int b1) {
        std::vector<xy> band;
        return specks_rows(m, min_area, b0, b1, band);
    });
    std::vector<xy> list;
    for (int b = 1; b < nb; b++) { // about each boundary, the whole sheet
        int y0 = std::max(0, b * SPECK_BAND - min_area),
            y1 = std::min(m->h, b * SPECK_BAND + min_area);
        for (int y = y0; y < y1; y++)
            for (int x = 0; x < m->w; x++)
                if (m->data[(size_t)y * m->stride + x] == UNSURE)
                    n += (size_t)fill_one(m, x, y, min_area, 0, m->h, list);
    }
#pragma omp parallel for schedule(static)
    for (int y = 0; y < m->h; y++) {
        uint8_t *row = m->data + (size_t)y * m->stride;
        for (int x = 0; x < m->w; x++)
            row[x] = row[x] != PAPER;
    }
    if (removed)
        *removed = n;
    return td_progress(cx, "specks", 1.0);
}

// Otsu from a histogram; see td_cv_otsu_hist.  Between-class variance of
// the split "<= t | > t" is w0 w1 (m1 - m0)^2 (weights as fractions).
int otsu_hist(const uint64_t *hist, int *thr)
{
    double total = 0, sum = 0;
    for (int i = 0; i < 256; i++) {
        total += (double)hist[i];
        sum += (double)i * (double)hist[i];
    }
    if (total <= 0)
        return -1;
    double n0 = 0, s0 = 0, best = 0;
    int t = 0;
    for (int i = 0; i < 256; i++) {
        n0 += (double)hist[i];
        s0 += (double)i * (double)hist[i];
        double w0 = n0 / total, w1 = 1.0 - w0;
        if (std::min(w0, w1) < FLT_EPSILON ||
            std::max(w0, w1) > 1.0 - FLT_EPSILON)
            continue;
        double m0 = s0 / n0, m1 = (sum - s0) / (total - n0);
        double var = w0 * w1 * (m1 - m0) * (m1 - m0);
        if (var > best) {
            best = var;
            t = i;
        }
    }
    *thr = t;
    return 0;
}

// ---- ximgproc thinning (benchmark anchor) -----------------------------

// cv::ximgproc::thinning(InputArray, OutputArray, int), looked up at run
// time: opencv_contrib is optional, and a weak reference would not survive
// the linker's --as-needed.  THINNING_ZHANGSUEN is 0.
typedef void (*thinning_fn)(const cv::_InputArray &, const cv::_OutputArray &,
                            int);
const char THINNING_SYM[] =
    "_ZN2cv8ximgproc8thinningERKNS_11_InputArrayERKNS_12_OutputArrayEi";

void *open_ximgproc()
{
    const std::string v = std::to_string(CV_VERSION_MAJOR),
                      m = std::to_string(CV_VERSION_MINOR);
    const std::string names[] = {"libopencv_ximgproc.so." + v + m,
                                 "libopencv_ximgproc.so." + v + "." + m,
                                 "libopencv_ximgproc.so"};
    for (const std::string &n : names)
        if (void *h = dlopen(n.c_str(), RTLD_NOW | RTLD_LOCAL))
            return h;
    return nullptr;
}

int thin_zhangsuen(td_grid_u8 *g, td_ctx *cx)
{
    void *lib = dlsym(RTLD_DEFAULT, THINNING_SYM) ? nullptr : open_ximgproc();
    void *sym =
        lib ? dlsym(lib, THINNING_SYM) : dlsym(RTLD_DEFAULT, THINNING_SYM);
    if (!sym) {
        if (lib)
            dlclose(lib);
        return td_seterr(cx, TD_EINVAL,
                         "OpenCV ximgproc (opencv_contrib) is not available");
    }
    thinning_fn thin = reinterpret_cast<thinning_fn>(sym);
    cv::Mat in = wrap_grid(g) != 0, out; // 0/255, as ximgproc wants
    try {
        thin(in, out, 0);
    } catch (...) {
        if (lib)
            dlclose(lib);
        throw;
    }
    if (lib)
        dlclose(lib);
    for (int y = 0; y < g->h; y++) {
        uint8_t *row = g->data + (size_t)y * g->stride;
        const uchar *o = out.ptr<uchar>(y);
        for (int x = 0; x < g->w; x++)
            row[x] = o[x] != 0;
    }
    return 0;
}

} // namespace

extern "C" {

int td_cv_read_jpeg(const char *path, td_image **out, td_ctx *cx)
{
    *out = nullptr;
    return guarded(path, cx, [&] { return read_jpeg(path, out, cx); });
}

// im (grey or RGB) encoded as JPEG at quality into bytes; what names im in
// messages.  0 or an error.
static int encode_jpeg(const td_image *im, int quality, const char *what,
                       std::vector<uchar> &bytes, td_ctx *cx)
{
    if (!im || !im->data || (im->channels != 1 && im->channels != 3) ||
        quality < 1 || quality > 100)
        return td_seterr(cx, TD_EINVAL, "%s: bad image or quality", what);
    cv::Mat src(im->h, im->w, CV_8UC(im->channels), im->data, im->stride),
        bgr;
    if (im->channels == 3)
        cv::cvtColor(src, bgr, cv::COLOR_RGB2BGR);
    else
        bgr = src;
    std::vector<int> opt = {cv::IMWRITE_JPEG_QUALITY, quality};
    if (!cv::imencode(".jpg", bgr, bytes, opt))
        return td_seterr(cx, TD_EFORMAT, "%s: cannot encode JPEG", what);
    return 0;
}

int td_cv_write_jpeg(const char *path, const td_image *im, int quality,
                     td_ctx *cx)
{
    return guarded(path, cx, [&] {
        std::vector<uchar> bytes;
        int rc = encode_jpeg(im, quality, path, bytes, cx);
        return rc != 0 ? rc : write_file_atomic(path, bytes, cx);
    });
}

int td_cv_jpeg_roundtrip(td_image *im, int quality, td_ctx *cx)
{
    return guarded("jpeg", cx, [&] {
        std::vector<uchar> bytes;
        int rc = encode_jpeg(im, quality, "jpeg", bytes, cx);
        if (rc != 0)
            return rc;
        int ch = im->channels;
        cv::Mat src(im->h, im->w, CV_8UC(ch), im->data, im->stride);
        cv::Mat dec = cv::imdecode(bytes, ch == 1 ? cv::IMREAD_GRAYSCALE
                                                  : cv::IMREAD_COLOR);
        if (dec.rows != im->h || dec.cols != im->w || dec.type() != CV_8UC(ch))
            return td_seterr(cx, TD_EFORMAT, "jpeg: cannot decode");
        if (ch == 3)
            cv::cvtColor(dec, src, cv::COLOR_BGR2RGB);
        else
            dec.copyTo(src);
        return 0;
    });
}

int td_cv_rgb_to_lab(const uint8_t *rgb, size_t n, float *lab, td_ctx *cx)
{
    return guarded("lab", cx, [&] {
        if (n == 0)
            return 0;
        if (n > (size_t)INT_MAX)
            return td_seterr(cx, TD_EINVAL, "lab: too many colours");
        cv::Mat in(1, (int)n, CV_8UC3, const_cast<uint8_t *>(rgb)), f;
        cv::Mat out(1, (int)n, CV_32FC3, lab);
        in.convertTo(f, CV_32FC3, 1.0 / 255.0);
        cv::cvtColor(f, out, cv::COLOR_RGB2Lab);
        if (out.data != (uchar *)lab)
            return td_seterr(cx, TD_EINTERNAL, "lab: OpenCV moved the output");
        return 0;
    });
}

// OpenCV builds its CIELAB tables on its first conversion, 0.13-0.17 s
// on one thread (measured 2026-12-06); a thread of its own builds them
// while a colour scan is read (the palette converts next).  Joined before
// the reader returns: OpenCV does not lock that first build.
struct td_cv_warm {
    std::thread t;
};

void *td_cv_lab_warm_begin(void)
{
    try {
        td_cv_warm *w = new td_cv_warm;
        w->t = std::thread([] {
            try {
                cv::Mat f(1, 1, CV_32FC3, cv::Scalar(0.5, 0.5, 0.5)), o;
                cv::cvtColor(f, o, cv::COLOR_RGB2Lab);
            } catch (...) {
            }
        });
        return w;
    } catch (...) {
        return nullptr; // no thread: the palette builds them itself
    }
}

void td_cv_lab_warm_end(void *h)
{
    td_cv_warm *w = static_cast<td_cv_warm *>(h);
    if (!w)
        return;
    w->t.join();
    delete w;
}

/* cv::kmeans with `flags` (KMEANS_PP_CENTERS: seeds from a fixed RNG state;
 * KMEANS_USE_INITIAL_LABELS: label[] in holds the first clusters). */
static int kmeans_with(const float *pts, int n, int dim, int k, int attempts,
                       int flags, int *label, float *centre, td_ctx *cx)
{
    return guarded("kmeans", cx, [&] {
        if (n < k || k < 1 || dim < 1)
            return td_seterr(cx, TD_EINVAL, "kmeans: %d points for %d "
                             "clusters", n, k);
        cv::Mat data(n, dim, CV_32F, const_cast<float *>(pts));
        cv::Mat lab, cen;
        cv::RNG &rng = cv::theRNG();
        uint64 saved = rng.state;
        if (flags & cv::KMEANS_USE_INITIAL_LABELS) {
            lab.create(n, 1, CV_32S);
            for (int i = 0; i < n; i++)
                lab.at<int>(i) = label[i];
        }
        rng.state = 0x5eed5eedULL;
        cv::kmeans(data, k, lab,
                   cv::TermCriteria(cv::TermCriteria::EPS +
                                        cv::TermCriteria::COUNT,
                                    30, 0.05),
                   attempts, flags, cen);
        rng.state = saved;
        for (int i = 0; i < n; i++)
            label[i] = lab.at<int>(i);
        for (int i = 0; i < k; i++)
            for (int d = 0; d < dim; d++)
                centre[i * dim + d] = cen.at<float>(i, d);
        return 0;
    });
}

int td_cv_kmeans(const float *pts, int n, int dim, int k, int attempts,
                 int *label, float *centre, td_ctx *cx)
{
    return kmeans_with(pts, n, dim, k, attempts, cv::KMEANS_PP_CENTERS, label,
                       centre, cx);
}

int td_cv_kmeans_from(const float *pts, int n, int dim, int k, int *label,
                      float *centre, td_ctx *cx)
{
    return kmeans_with(pts, n, dim, k, 1, cv::KMEANS_USE_INITIAL_LABELS, label,
                       centre, cx);
}

int td_cv_rgb_to_grey(const td_image *im, td_grid_u8 *grey, td_ctx *cx)
{
    return guarded("grey", cx, [&] {
        int rc;
        if (!im || !im->data || (im->channels != 1 && im->channels != 3))
            return td_seterr(cx, TD_EINVAL, "grey: invalid image");
        if ((rc = check_grid(grey, "grey", cx)) != 0 ||
            (rc = same_size(grey, im->w, im->h, "grey", cx)) != 0)
            return rc;
        for (int y0 = 0; y0 < im->h; y0 += BAND) {
            int n = std::min(BAND, im->h - y0);
            cv::Mat src(n, im->w, CV_8UC(im->channels),
                        im->data + (size_t)y0 * im->stride, im->stride);
            cv::Mat dst(n, im->w, CV_8UC1,
                        grey->data + (size_t)y0 * grey->stride, grey->stride);
            if (im->channels == 3)
                cv::cvtColor(src, dst, cv::COLOR_RGB2GRAY);
            else
                src.copyTo(dst);
            if ((rc = td_progress(cx, "grey", (double)(y0 + n) / im->h)))
                return rc;
        }
        return 0;
    });
}

int td_cv_otsu_hist(const uint64_t hist[256], int *thr, td_ctx *cx)
{
    return guarded("otsu", cx, [&] {
        if (otsu_hist(hist, thr) != 0)
            return td_seterr(cx, TD_EINVAL, "otsu: empty histogram");
        return 0;
    });
}

int td_cv_otsu(const td_grid_u8 *g, int *thr, td_ctx *cx)
{
    return guarded("otsu", cx, [&] {
        int rc = check_grid(g, "otsu", cx);
        if (rc != 0)
            return rc;
        uint64_t hist[256] = {0};
        for (int y = 0; y < g->h; y++) {
            const uint8_t *row = g->data + (size_t)y * g->stride;
            for (int x = 0; x < g->w; x++)
                hist[row[x]]++;
        }
        return otsu_hist(hist, thr) == 0
                   ? 0
                   : td_seterr(cx, TD_EINVAL, "otsu: empty histogram");
    });
}

int td_cv_otsu_opencv(const td_grid_u8 *g, int *thr, td_ctx *cx)
{
    return guarded("otsu", cx, [&] {
        int rc = check_grid(g, "otsu", cx);
        if (rc != 0)
            return rc;
        cv::Mat tmp;
        double t = cv::threshold(wrap_grid(g), tmp, 0, 255,
                                 cv::THRESH_BINARY | cv::THRESH_OTSU);
        *thr = (int)t;
        return 0;
    });
}

int td_cv_sauvola(const td_grid_u8 *s, int window, double k, td_grid_u8 *mask,
                  td_ctx *cx)
{
    return guarded("sauvola", cx, [&] {
        int rc;
        if ((rc = check_grid(s, "sauvola", cx)) != 0 ||
            (rc = check_grid(mask, "sauvola", cx)) != 0 ||
            (rc = same_size(mask, s->w, s->h, "sauvola", cx)) != 0)
            return rc;
        if (window < 3 || window > 181 || window % 2 == 0)
            return td_seterr(cx, TD_EINVAL, "sauvola: window %d (odd, 3..181)",
                             window);
        if (!(k > 0.0 && k <= 1.0))
            return td_seterr(cx, TD_EINVAL, "sauvola: k %g (0 < k <= 1)", k);
        return sauvola(s, window, k, mask, cx);
    });
}

int td_cv_median3(td_grid_u8 *g, td_ctx *cx)
{
    return guarded("median3", cx, [&] {
        int rc = check_grid(g, "median3", cx);
        return rc != 0 ? rc : median3(g, cx);
    });
}

int td_cv_thin_zhangsuen(td_grid_u8 *g, td_ctx *cx)
{
    return guarded("thin (ximgproc)", cx, [&] {
        int rc = check_grid(g, "thin (ximgproc)", cx);
        return rc != 0 ? rc : thin_zhangsuen(g, cx);
    });
}

int td_cv_remove_specks(td_grid_u8 *mask, int min_area, size_t *removed,
                        td_ctx *cx)
{
    return guarded("specks", cx, [&] {
        int rc = check_grid(mask, "specks", cx);
        if (rc != 0)
            return rc;
        if (removed)
            *removed = 0;
        if (min_area <= 1) // every component has at least one cell
            return 0;
        return remove_specks(mask, min_area, removed, cx);
    });
}

int td_cv_fill_holes(td_grid_u8 *mask, int min_area, size_t *filled,
                     td_ctx *cx)
{
    return guarded("holes", cx, [&] {
        int rc = check_grid(mask, "holes", cx);
        if (rc != 0)
            return rc;
        if (filled)
            *filled = 0;
        if (min_area <= 1)
            return 0;
        return fill_holes(mask, min_area, filled, cx);
    });
}

int td_cv_delaunay(const double *xy, size_t n, int32_t **tri, size_t *ntri,
                   td_ctx *cx)
{
    *tri = NULL;
    *ntri = 0;
    return guarded("delaunay", cx, [&] {
        if (n < 3 || n > (size_t)INT_MAX / 4)
            return td_seterr(cx, TD_EINVAL, "delaunay: %zu points", n);
        float x0 = FLT_MAX, y0 = FLT_MAX, x1 = -FLT_MAX, y1 = -FLT_MAX;
        for (size_t i = 0; i < n; i++) {
            float x = (float)xy[2 * i], y = (float)xy[2 * i + 1];
            if (!std::isfinite(x) || !std::isfinite(y))
                return td_seterr(cx, TD_EINVAL, "delaunay: a non-finite point");
            x0 = std::min(x0, x), x1 = std::max(x1, x);
            y0 = std::min(y0, y), y1 = std::max(y1, y);
        }
        cv::Rect2f box(x0 - 1, y0 - 1, x1 - x0 + 3, y1 - y0 + 3);
        cv::Subdiv2D sd;
        sd.initDelaunay(cv::Rect((int)std::floor(box.x), (int)std::floor(box.y),
                                 (int)std::ceil(box.width) + 2,
                                 (int)std::ceil(box.height) + 2));
        // Subdiv2D numbers its vertices: 4 virtual ones first, then the
        // points in the order inserted (a repeated point keeps the first)
        std::vector<int> vid(n);
        for (size_t i = 0; i < n; i++)
            vid[i] = sd.insert(cv::Point2f((float)xy[2 * i], (float)xy[2 * i + 1]));
        std::vector<int> of(vid.empty() ? 0 : *std::max_element(vid.begin(),
                                                             vid.end()) + 1,
                            -1);
        for (size_t i = 0; i < n; i++)
            if (of[vid[i]] < 0)
                of[vid[i]] = (int)i;
        std::vector<cv::Vec6f> tl;
        sd.getTriangleList(tl);
        int32_t *t = (int32_t *)malloc((tl.size() * 3 + 1) * sizeof *t);
        if (!t)
            return td_seterr(cx, TD_ENOMEM, "delaunay: out of memory");
        size_t m = 0;
        for (const cv::Vec6f &v : tl) {
            int idx[3], ok = 1;
            for (int k = 0; k < 3 && ok; k++) {
                int e = 0, vtx = 0;
                int r = sd.locate(cv::Point2f(v[2 * k], v[2 * k + 1]), e, vtx);
                ok = r == cv::Subdiv2D::PTLOC_VERTEX && vtx >= 0 &&
                     vtx < (int)of.size() && of[vtx] >= 0;
                if (ok)
                    idx[k] = of[vtx];
            }
            if (!ok)
                continue; // a corner is one of the virtual outer vertices
            t[3 * m] = idx[0], t[3 * m + 1] = idx[1], t[3 * m + 2] = idx[2];
            m++;
        }
        *tri = t;
        *ntri = m;
        return 0;
    });
}

} // extern "C"
