/* replay_main.c: feed each file named on the command line to the fuzz
 * target once (saved crashes and the seed corpus, under ASan in make
 * check).  Exits 0 when nothing crashed; a crash ends the process. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int main(int argc, char **argv)
{
    int i, n = 0;
    for (i = 1; i < argc; i++) {
        FILE *f = fopen(argv[i], "rb");
        uint8_t *buf;
        long len;
        if (!f)
            continue; /* e.g. an unexpanded glob: nothing to replay */
        fseek(f, 0, SEEK_END);
        len = ftell(f);
        fseek(f, 0, SEEK_SET);
        buf = malloc(len > 0 ? (size_t)len : 1);
        if (buf && (len <= 0 || fread(buf, 1, (size_t)len, f) == (size_t)len)) {
            LLVMFuzzerTestOneInput(buf, len > 0 ? (size_t)len : 0);
            n++;
        }
        free(buf);
        fclose(f);
    }
    printf("replayed %d inputs\n", n);
    return 0;
}
