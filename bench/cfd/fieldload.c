/* fieldload.c -- bench_cfd fieldload: what reading an airwake field costs,
 * and the share of it its two checksums take (the file's seal and the
 * data's data_crc64, cfd/io.c), against the baseline CRC-64 in the same
 * run.
 *
 *   bench_cfd fieldload [--ship NAME] [--grid coarse|default|fine]
 *       [--rounds N]
 *
 * The field: the ship (SFS2) at 15 m/s from ahead with the UH-60A's disk
 * on the grid asked for, one SIMPLEC iteration (its size is what counts,
 * not its convergence), written sealed to a temporary file. Each round
 * then times, on that file (in the page cache after the first):
 *   - cfd_field_load (the seal's CRC over the file, HDF5's read, the
 *     data's CRC, the checks);
 *   - the CRC-64 of the whole file by core_crc64 (eight bytes a step);
 *   - the same by the baseline: the byte-at-a-time table CRC-64/XZ both
 *     cfd and awdb used before core_crc64 (its table here).
 * Printed: the file's size, the best of the rounds for each, the
 * baseline's time over core_crc64's (the ratio), and the two checksums'
 * share of the load (two passes of core_crc64 over the file's bytes). */
#include "bench_cfd.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The baseline: CRC-64/XZ a byte a step from a 256-entry table. */
static void base_table(uint64_t t[256])
{
    for (unsigned i = 0; i < 256; i++) {
        uint64_t r = i;
        for (int b = 0; b < 8; b++)
            r = r & 1 ? (r >> 1) ^ 0xC96C5795D7870F42ULL : r >> 1;
        t[i] = r;
    }
}

static uint64_t base_crc(const uint64_t t[256], const unsigned char *p, size_t n)
{
    uint64_t c = ~0ULL;
    for (size_t i = 0; i < n; i++)
        c = t[(c ^ p[i]) & 0xFF] ^ (c >> 8);
    return ~c;
}

/* The whole file into memory: its bytes (malloc'ed) and size, or NULL. */
static unsigned char *slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    struct stat st;
    unsigned char *b = NULL;
    if (f && fstat(fileno(f), &st) == 0 && (b = malloc((size_t)st.st_size + 1)) &&
        fread(b, 1, (size_t)st.st_size, f) == (size_t)st.st_size)
        *n = (size_t)st.st_size;
    else {
        free(b);
        b = NULL;
    }
    if (f)
        fclose(f);
    return b;
}

int bench_cfd_fieldload(const char *ship_name, core_grid_level lv, int rounds)
{
    core_ship ship;
    cfd_airwake_spec sp;
    if (bench_cfd_setup_ship(&ship, &sp, ship_name, 15.0, lv, 0.0, 1))
        return 1;
    sp.max_iter = 1;
    core_err err = {0};
    char path[] = "/tmp/bench_cfd_load_XXXXXX";
    int fd = mkstemp(path);
    if (fd < 0) {
        perror("bench_cfd: mkstemp");
        return 1;
    }
    close(fd);
    cfd_result res;
    cfd_meta meta;
    memset(&meta, 0, sizeof meta);
    meta.wod_speed_mps = 15.0;
    snprintf(meta.ship, sizeof meta.ship, "%s", ship.name);
    snprintf(meta.rotor, sizeof meta.rotor, "uniform");
    snprintf(meta.grid, sizeof meta.grid, "%s", core_grid_name(lv));
    cfd_solver *s = cfd_airwake_create(&sp, NULL, NULL, NULL, &err);
    int bad = !s || cfd_solver_run(s, &res, &err) < 0 || cfd_solver_write(s, &meta, path, &err) != 0;
    size_t cells = s ? cfd_grid_cells(cfd_solver_grid(s)) : 0;
    cfd_solver_destroy(s);
    size_t n = 0;
    unsigned char *bytes = bad ? NULL : slurp(path, &n);
    if (bad || !bytes) {
        fprintf(stderr, "bench_cfd fieldload: %s\n", err.msg[0] ? err.msg : "cannot read the field back");
        unlink(path);
        free(bytes);
        return 1;
    }
    static uint64_t t[256];
    base_table(t);
    double best_load = 1e30, best_crc = 1e30, best_base = 1e30;
    uint64_t c1 = 0, c2 = 0;
    for (int r = 0; r < rounds && !bad; r++) {
        double t0 = now_s();
        cfd_field *f = cfd_field_load(path, &err);
        double t1 = now_s();
        c1 = core_crc64(0, bytes, n);
        double t2 = now_s();
        c2 = base_crc(t, bytes, n);
        double t3 = now_s();
        bad = !f || !cfd_field_meta(f)->sealed || c1 != c2;
        cfd_field_destroy(f);
        if (t1 - t0 < best_load)
            best_load = t1 - t0;
        if (t2 - t1 < best_crc)
            best_crc = t2 - t1;
        if (t3 - t2 < best_base)
            best_base = t3 - t2;
    }
    unlink(path);
    free(bytes);
    char xmf[64];
    snprintf(xmf, sizeof xmf, "%s.xmf", path);
    unlink(xmf);
    if (bad) {
        fprintf(stderr, "bench_cfd fieldload: %s\n",
                err.msg[0] ? err.msg : c1 != c2 ? "the two CRC-64s differ" : "the field did not load sealed");
        return 1;
    }
    printf("fieldload: %s, %s grid, %zu cells, a sealed field of %.1f MB, best of %d rounds\n", ship.name,
           core_grid_name(lv), cells, (double)n / 1e6, rounds);
    printf("  cfd_field_load (seal, HDF5, data CRC)  %8.4f s\n", best_load);
    printf("  CRC-64 of the file, core_crc64         %8.4f s  (%.2f GB/s)\n", best_crc, (double)n / best_crc / 1e9);
    printf("  CRC-64 of the file, baseline (a byte)  %8.4f s  (%.2f GB/s)\n", best_base, (double)n / best_base / 1e9);
    printf("  baseline / core_crc64                  %8.2f\n", best_base / best_crc);
    printf("  the two checksums' share of the load   %7.1f %%  (%.1f %% with the baseline's)\n",
           100.0 * 2.0 * best_crc / best_load, 100.0 * 2.0 * best_base / (best_load - 2.0 * best_crc + 2.0 * best_base));
    return 0;
}
