// test_skeleton_cgal.cpp: the straight skeleton of src/model/skeleton.c
// (the paper's construction, and skeleton_queue.c, the event queue beside
// it: each outline by both) against CGAL's Straight_skeleton_2 on a few
// hundred random outlines with reflex corners (star-shaped: random radii
// at sorted random angles, so simple): every node CGAL finds inside (its
// position and the time the front reaches it) is one of ours within 1e-6
// of the outline's size, and every node of ours is one of CGAL's.  Built
// only where CGAL is installed (libcgal-dev); the project does not link it.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/create_straight_skeleton_2.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

extern "C" {
#include "src/model/model.h"
}

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Polygon_2<K> Polygon;

static uint64_t rng = 0x243F6A8885A308D3u;
static double urand()
{
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0;
}

int main()
{
    int passed = 0, failed = 0, polys = 300, worst_k = -1;
    double worst = 0;
    for (int k = 0; k < polys; k++) {
        int n = 5 + (int)(urand() * 36);
        std::vector<double> a(n), xy(2 * n);
        for (int i = 0; i < n; i++)
            a[i] = urand() * 2 * M_PI;
        std::sort(a.begin(), a.end());
        Polygon poly;
        for (int i = 0; i < n; i++) {
            double r = 20 + 40 * urand();
            xy[2 * i] = 100 + r * std::cos(a[i]);
            xy[2 * i + 1] = 100 + r * std::sin(a[i]);
            poly.push_back(K::Point_2(xy[2 * i], xy[2 * i + 1]));
        }
        if (!poly.is_simple() || poly.area() <= 1)
            continue;
        auto ss = CGAL::create_interior_straight_skeleton_2(
            poly.vertices_begin(), poly.vertices_end(), K());
        for (int con = TD_SKEL_PAPER; con <= TD_SKEL_QUEUE; con++) {
        td_lines *nodes = td_lines_new(NULL);
        td_skeleton_params p = td_skeleton_defaults();
        p.nodes = nodes;
        p.construction = con;
        int rc = td_skeleton(xy.data(), (size_t)n, &p, NULL, NULL, NULL, NULL,
                             NULL);
        double err = 0, tol = 1e-6 * 120;
        if (rc == 0 && ss) {
            // CGAL's inner nodes among ours
            for (auto v = ss->vertices_begin(); v != ss->vertices_end(); ++v) {
                if (!v->is_skeleton())
                    continue;
                double x = v->point().x(), y = v->point().y(), t = v->time();
                double best = HUGE_VAL;
                for (size_t j = 0; j < nodes->n; j++)
                    best = std::min(best,
                                    std::max(std::hypot(nodes->v[j].xy[0] - x,
                                                        nodes->v[j].xy[1] - y),
                                             std::fabs(nodes->v[j].height - t)));
                err = std::max(err, best);
            }
            // ours among CGAL's
            for (size_t j = 0; j < nodes->n; j++) {
                double best = HUGE_VAL;
                for (auto v = ss->vertices_begin(); v != ss->vertices_end();
                     ++v)
                    if (v->is_skeleton())
                        best = std::min(
                            best,
                            std::max(std::hypot(v->point().x() - nodes->v[j].xy[0],
                                                v->point().y() - nodes->v[j].xy[1]),
                                     std::fabs(v->time() - nodes->v[j].height)));
                err = std::max(err, best);
            }
        }
        if (rc != 0 || !ss || !(err <= tol)) {
            failed++;
            if (failed <= 5)
                std::fprintf(stderr, "  FAIL outline %d (%d corners, %s): "
                             "rc %d, largest node mismatch %g (tolerance "
                             "%g)\n", k, n, con == TD_SKEL_PAPER ? "paper" :
                             "queue", rc, err, tol);
        } else {
            passed++;
        }
        if (err > worst)
            worst = err, worst_k = k;
        td_lines_free(nodes);
        }
    }
    std::printf("ok   %d skeletons (paper's and queue's) agree with CGAL's skeleton (worst node "
                "mismatch %g, outline %d)\n", passed, worst, worst_k);
    std::printf("%d passed, %d failed\n", passed, failed);
    return failed != 0;
}
