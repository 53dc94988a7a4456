#define _POSIX_C_SOURCE 200809L
#include "tests/tt.h"

#include <stdlib.h>
#include <string.h>

int tt_passed, tt_failed, tt_cur_failed;
const char *tt_cur_name = "";

int tt_summary(void)
{
    printf("%d passed, %d failed\n", tt_passed, tt_failed);
    return tt_failed ? 1 : 0;
}

const char *tt_tmpdir(void)
{
    static char dir[512];
    if (!dir[0]) {
        const char *t = getenv("TMPDIR");
        snprintf(dir, sizeof dir, "%s/tdtest.XXXXXX", t && *t ? t : "/tmp");
        if (!mkdtemp(dir)) {
            perror("mkdtemp");
            exit(2);
        }
    }
    return dir;
}
