/* io.h -- private: output folder and atomic file writes for shol's outputs.
 * Each file is written under a temporary name in the same folder and
 * renamed into place, so a reader never sees half a file. */
#ifndef DISIM_SHOL_IO_H
#define DISIM_SHOL_IO_H

#include "shol.h"

#include <stdio.h>

#define SHOL_IO_PATH_MAX 1024

/* Create dir and its parents if missing; < 0 with err if it cannot, or if
 * it exists and is not a folder. */
int shol_io_mkdir(const char *dir, core_err *err);
/* An output set written whole or not at all: begin creates dir and a
 * staging folder in it (stage, SHOL_IO_PATH_MAX); the writers write
 * there; commit checks that no target in dir is a folder, a device or a
 * FIFO, then renames every file into dir; abort (and a failed commit)
 * removes the staging folder and what is in it. */
int shol_io_stage_begin(const char *dir, char *stage, core_err *err);
int shol_io_stage_commit(const char *dir, const char *stage, core_err *err);
void shol_io_stage_abort(const char *stage);
/* Fill final = dir/name and tmp = a temporary name beside it. */
int shol_io_paths(const char *dir, const char *name, char *final, char *tmp, core_err *err);
/* Open tmp for writing (after shol_io_paths). */
FILE *shol_io_open(const char *tmp, core_err *err);
/* Flush and close f (if not NULL) and rename tmp to final; on any error
 * (including a stream error seen by ferror) remove tmp and return < 0. */
int shol_io_commit(FILE *f, const char *tmp, const char *final, core_err *err);
/* Remove tmp after a failed write. */
void shol_io_abort(FILE *f, const char *tmp);
/* A JSON string with the escapes JSON needs; text that is not
 * well-formed UTF-8 (a path in Latin-1) written as U+FFFD, byte by byte,
 * so that a JSON reader takes the file (RFC 8259 section 8.1). */
void shol_io_json_str(FILE *f, const char *s);
/* A JSON number: printf(fmt, v), or null where v is not finite. */
void shol_io_json_num(FILE *f, const char *fmt, double v);
/* Write "nan" for a non-finite value, else printf(fmt, v). */
void shol_io_num(FILE *f, const char *fmt, double v);
/* A direction's band as CSV columns (each preceded by its comma):
 * lo, hi, grid, window, sens in km/h (fmt, "nan" where absent), then
 * open_above and low_confidence, then model in km/h. */
void shol_io_band_csv(FILE *f, const shol_band *b, const char *fmt);
/* The same as a JSON object {"lo_kmh": ..., "model_kmh": ...,
 * "model_quantity": ..., "model_error": ..., "model_reference": ...,
 * "low_confidence": ...}, the numbers by fmt, null where absent. */
void shol_io_band_json(FILE *f, const shol_band *b, const char *fmt);

#endif
