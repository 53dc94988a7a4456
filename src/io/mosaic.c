/* mosaic.c: the DEMs of a map series as one (GDAL's BuildVRT): a VRT over
 * the sheet DEMs where they lie, or one tiled, compressed GeoTIFF.
 * Written under a temporary name beside the output and renamed. */
#include "src/io/io.h"

#include <cpl_error.h>
#include <gdal.h>
#include <gdal_utils.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

static int ends(const char *s, const char *e)
{
    size_t a = strlen(s), b = strlen(e);
    return a >= b && !strcasecmp(s + a - b, e);
}

/* See io.h. */
int td_dem_mosaic(const char *const *in, size_t n, const char *out,
                  td_ctx *cx)
{
    char *bv[] = {"-resolution", "highest", NULL};
    char *tv[] = {"-of", "GTiff", "-co", "TILED=YES", "-co",
                  "COMPRESS=DEFLATE", "-co", "PREDICTOR=3", "-co",
                  "BIGTIFF=IF_SAFER", NULL};
    int vrt = ends(out, ".vrt"), err = 0, rc = 0;
    size_t tl = strlen(out) + 32;
    char *tmp = malloc(tl);
    GDALBuildVRTOptions *bo = NULL;
    GDALTranslateOptions *to = NULL;
    GDALDatasetH ds = NULL, t = NULL;
    if (!tmp)
        return td_seterr(cx, TD_ENOMEM, "out of memory");
    if (!vrt && !ends(out, ".tif") && !ends(out, ".tiff")) {
        free(tmp);
        return td_seterr(cx, TD_EINVAL, "%s: a mosaic is written as .vrt or "
                         ".tif", out);
    }
    if (n == 0) {
        free(tmp);
        return td_seterr(cx, TD_EINVAL, "%s: no DEMs to put together", out);
    }
    if ((rc = td_atomic_check_target(out, cx)) != 0) {
        free(tmp);
        return rc;
    }
    snprintf(tmp, tl, "%s.tmp.%ld", out, (long)getpid());
    GDALAllRegister();
    CPLErrorReset();
    CPLPushErrorHandler(CPLQuietErrorHandler);
    bo = GDALBuildVRTOptionsNew(bv, NULL);
    ds = GDALBuildVRT(vrt ? tmp : "", (int)n, NULL, (const char *const *)in,
                      bo, &err);
    if (!ds || err) {
        rc = td_seterr(cx, TD_EIO, "%s: cannot put the DEMs together: %s", out,
                       CPLGetLastErrorMsg()[0] ? CPLGetLastErrorMsg()
                                               : "GDAL BuildVRT failed");
        goto done;
    }
    if (!vrt) {
        GDALDataType ty = GDALGetRasterDataType(GDALGetRasterBand(ds, 1));
        if (ty != GDT_Float32 && ty != GDT_Float64)
            tv[7] = "PREDICTOR=2"; /* the float predictor takes floats only */
        to = GDALTranslateOptionsNew(tv, NULL);
        t = GDALTranslate(tmp, ds, to, &err);
        if (!t || err)
            rc = td_seterr(cx, TD_EIO, "%s: %s", out,
                           CPLGetLastErrorMsg()[0] ? CPLGetLastErrorMsg()
                                                   : "cannot write");
        if (t)
            GDALClose(t);
    }
    GDALClose(ds);
    ds = NULL;
    if (rc == 0 && CPLGetLastErrorType() >= CE_Failure)
        rc = td_seterr(cx, TD_EIO, "%s: %s", out, CPLGetLastErrorMsg());
    if (rc == 0 && rename(tmp, out) != 0)
        rc = td_seterr(cx, TD_EIO, "%s: cannot rename the temporary file", out);
done:
    if (ds)
        GDALClose(ds);
    if (rc != 0)
        unlink(tmp);
    CPLPopErrorHandler();
    GDALBuildVRTOptionsFree(bo);
    if (to)
        GDALTranslateOptionsFree(to);
    free(tmp);
    return rc;
}
