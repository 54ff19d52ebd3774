/* bench_cfd.h -- what bench_cfd's modes share across its files: the
 * benchmark case (a ship in a wind, the UH-60A's uniform disk), the
 * side-by-side mode (sidebyside.c) and the field-load mode (fieldload.c). */
#ifndef DISIM_BENCH_CFD_H
#define DISIM_BENCH_CFD_H

#include "cfd.h"

/* scenarios/ships/NAME.ini in speed_mps from dir_deg on level lv; rotor 1:
 * the UH-60A uniform disk (T = m g, m 7438.91 kg, R 8.18 m) hovering one
 * radius over the spot; the monitors 6.8 m over the deck. 0, or -1 with
 * the error printed. */
int bench_cfd_setup_ship(core_ship *ship, cfd_airwake_spec *sp, const char *name, double speed_mps,
                         core_grid_level lv, double dir_deg, int rotor);

/* bench_cfd sidebyside OPTIONS (argv[0] is the first option): the
 * embedded solver and OpenFOAM on the same case (sidebyside.c). The exit
 * status: 0 done, 1 failed, 2 bad options. */
int bench_cfd_sidebyside(int argc, char **argv);

/* bench_cfd fieldload: cfd_field_load's time on a sealed field of ship on
 * level lv, and its two checksums' share, against the baseline CRC-64 in
 * the same run (fieldload.c). 0, or 1 with the error printed. */
int bench_cfd_fieldload(const char *ship_name, core_grid_level lv, int rounds);

#endif
