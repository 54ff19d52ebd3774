/* fuzz_field.c -- libFuzzer harness of the airwake field reader
 * (cfd_field_load): each input is written to a file on tmpfs (/dev/shm;
 * HDF5 reads files, not memory), sealed again when its length is even
 * (cfd_field_seal: below) and loaded, which checks the file's seal (its
 * size and CRC-64) and reads the HDF5
 * attributes (strings and numbers, each of one element), the datasets'
 * ranks and extents against the grid, the node coordinates (finite,
 * increasing), the solid mask, the seven variables (finite) and the data's
 * checksum. A field that loads is sampled inside, at its edges and far
 * outside (cfd_field_sample, cfd_field_air), written again
 * (cfd_field_write) and, when ship-only, mirrored (cfd_field_mirror_y).
 * Checked, beyond no crash, hang, leak or sanitizer report: a refused file
 * says why; every sample of a loaded field is finite. HDF5 itself is not
 * instrumented: the coverage is disim's own code. */
#include "cfd.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
const char *__asan_default_options(void);
const char *__lsan_default_suppressions(void);

/* HDF5 asks for what a corrupt header says (up to 2^64 bytes) and handles
 * a NULL from malloc: here malloc returns NULL too, as the C library does,
 * instead of ASan's report of a size it cannot give. */
const char *__asan_default_options(void) { return "allocator_may_return_null=1"; }
/* libhdf5 1.10.8 leaks the metadata cache entry it was loading when the
 * entry does not deserialize (a corrupt object header met by H5Fopen or
 * H5Dopen2: H5C_protect), after it has returned the error to disim: its
 * own memory. Nothing disim holds can be among what is suppressed: an
 * HDF5 handle left open stays reachable through the library's tables, and
 * disim's own allocations are not made in libhdf5. */
const char *__lsan_default_suppressions(void) { return "leak:libhdf5_serial.so\n"; }

static char in_path[128], out_path[128], out_xmf[128];

static void sample_all(const cfd_field *f)
{
    int n[3];
    cfd_field_dims(f, n);
    static const double pts[][3] = {{0, 0, 0}, {1, 0.5, 0.5}, {-1e9, 1e9, 0}, {1e300, -1e300, 1e300}, {2, 0.3, 0.1}};
    for (size_t i = 0; i < sizeof pts / sizeof pts[0]; i++) {
        double out[CFD_NVARS], vel[3];
        cfd_field_sample(f, pts[i], out);
        for (int v = 0; v < CFD_NVARS; v++)
            if (!isfinite(out[v]))
                abort(); /* a loaded field sampled to a NaN or infinity */
        cfd_field_air((void *)f, pts[i], 0.0, vel);
        if (!isfinite(vel[0]) || !isfinite(vel[1]) || !isfinite(vel[2]))
            abort();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (!in_path[0]) {
        snprintf(in_path, sizeof in_path, "/dev/shm/disim_fuzz_field.%ld.h5", (long)getpid());
        snprintf(out_path, sizeof out_path, "/dev/shm/disim_fuzz_field_out.%ld.h5", (long)getpid());
        snprintf(out_xmf, sizeof out_xmf, "/dev/shm/disim_fuzz_field_out.%ld.xmf", (long)getpid());
    }
    FILE *fp = fopen(in_path, "wb");
    if (!fp || (size && fwrite(data, 1, size, fp) != size) || fclose(fp) != 0)
        abort(); /* the harness itself cannot run */
    core_err err = {0};
    /* An input of even length is sealed again (when it has the user block
     * for it), so that what lies behind the seal is fuzzed: the loader's
     * HDF5 reading and libhdf5; one of odd length is loaded as it is, and
     * the seal's own checks are. */
    if (size % 2 == 0)
        cfd_field_seal(in_path, &err);
    err.msg[0] = '\0';
    cfd_field *f = cfd_field_load(in_path, &err);
    if (!f) {
        if (!err.msg[0])
            abort(); /* refused without a word */
        return 0;
    }
    sample_all(f);
    if (cfd_field_write(f, out_path, &err) == 0) {
        cfd_field *g = cfd_field_load(out_path, &err);
        if (!g)
            abort(); /* what was read and written again cannot be read */
        cfd_field_destroy(g);
    }
    cfd_field *m = cfd_field_mirror_y(f, &err);
    if (m)
        sample_all(m);
    cfd_field_destroy(m);
    cfd_field_destroy(f);
    unlink(out_path);
    unlink(out_xmf);
    return 0;
}
