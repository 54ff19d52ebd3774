/* fuzz_lcm_log.c -- libFuzzer harness of the LCM log reader (sim/log.c):
 * each input is written to a file on tmpfs (/dev/shm: the reader is lcm's
 * event log, which reads files) and read by sim_log_check_frames (the
 * framing every reader checks first) and sim_log_load (the whole reader:
 * framing, disim_lcm_check_raw, the decoders, the states' checks). Built
 * with -DDISIM_FUZZ=ON and clang; run from the source root:
 *   build-fuzz/tests/fuzz/fuzz_lcm_log -max_total_time=60 CORPUS_DIR
 * A crash, a hang or a sanitizer report is a failure. */
#include "sim.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static char path[64];
    if (!path[0])
        snprintf(path, sizeof path, "/dev/shm/disim_fuzz_lcm_log.%d.lcm", (int)getpid());
    FILE *f = fopen(path, "wb");
    if (!f)
        abort(); /* the harness itself cannot run */
    if (size && fwrite(data, 1, size, f) != size)
        abort();
    fclose(f);
    core_err err = {0};
    sim_log_frames fr;
    int framed = sim_log_check_frames(path, &fr, &err) == 0;
    sim_log *L = sim_log_load(path, &err);
    if (L && !framed)
        abort(); /* the whole reader took what the framing refused */
    if (L) {
        sim_log_summary s;
        sim_log_info(L, &s);
        sim_log_sample smp;
        sim_log_state st;
        sim_log_sample_at(L, 0.5 * (s.t0_s + s.t1_s), &smp);
        sim_log_state_at(L, s.t1_s + 1.0, &st);
    }
    sim_log_destroy(L);
    return 0;
}
