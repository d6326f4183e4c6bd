/* Replays inputs through a fuzz harness without libFuzzer, so that the corpora run under gcc
   (with AddressSanitizer and UndefinedBehaviorSanitizer) in the ordinary tests. Link with one
   fuzz_<name>.c; every argument is a file, or a directory whose files are all replayed.
   Prints "replayed N inputs" and exits 0; a broken invariant or a sanitizer finding aborts. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Feed one file to the harness; 0 when it cannot be read. */
static int replay_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    unsigned char *data = NULL;
    size_t size = 0, capacity = 0, got;
    if (!f) return 0;
    do {
        if (size == capacity) {
            unsigned char *grown;
            capacity = capacity ? 2 * capacity : 65536;
            grown = (unsigned char *)realloc(data, capacity);
            if (!grown) {
                free(data);
                fclose(f);
                return 0;
            }
            data = grown;
        }
        got = fread(data + size, 1, capacity - size, f);
        size += got;
    } while (got > 0);
    fclose(f);
    /* an exact-size copy, so that AddressSanitizer sees any read past the end */
    {
        unsigned char *exact = (unsigned char *)malloc(size ? size : 1);
        if (!exact) {
            free(data);
            return 0;
        }
        if (size) memcpy(exact, data, size);
        free(data);
        LLVMFuzzerTestOneInput(exact, size);
        free(exact);
    }
    return 1;
}

int main(int argc, char **argv)
{
    long replayed = 0;
    int i, failed = 0;
    for (i = 1; i < argc; ++i) {
        struct stat st;
        if (stat(argv[i], &st) != 0) {
            fprintf(stderr, "replay: cannot find %s\n", argv[i]);
            failed = 1;
        } else if (S_ISDIR(st.st_mode)) {
            DIR *dir = opendir(argv[i]);
            struct dirent *entry;
            if (!dir) {
                fprintf(stderr, "replay: cannot open %s\n", argv[i]);
                failed = 1;
                continue;
            }
            while ((entry = readdir(dir)) != NULL) {
                char path[4096];
                struct stat est;
                snprintf(path, sizeof path, "%s/%s", argv[i], entry->d_name);
                if (stat(path, &est) != 0 || !S_ISREG(est.st_mode)) continue;
                if (replay_file(path)) ++replayed;
                else {
                    fprintf(stderr, "replay: cannot read %s\n", path);
                    failed = 1;
                }
            }
            closedir(dir);
        } else if (replay_file(argv[i])) {
            ++replayed;
        } else {
            fprintf(stderr, "replay: cannot read %s\n", argv[i]);
            failed = 1;
        }
    }
    printf("replayed %ld inputs\n", replayed);
    return failed;
}
