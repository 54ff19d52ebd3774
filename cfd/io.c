/*
 * io.c -- airwake fields in HDF5 with an XDMF side file, and the loader.
 *
 * Layout (HDF5, C API): /grid/{x,y,z}_nodes (m, frame S), /grid/solid
 * (uint8, nz x ny x nx), /fields/{u,v,w,p,k,epsilon,nu_t} (float64,
 * nz x ny x nx, x fastest; cell centred; m/s, Pa, m^2/s^2, m^2/s^3, m^2/s),
 * /residuals (iterations x 5: continuity, u, v, w, k, normalised), root
 * attributes for the metadata, after a 512-byte user block holding the
 * file's seal (its size and CRC-64, checked before HDF5 opens it: below).
 * The XDMF file describes a 3DRectMesh with
 * cell-centred attributes so ParaView opens it; coordinates stay in frame
 * S (z down, not flipped), which the file states. Both files are written to
 * a temporary name and renamed, so a reader never sees half a field.
 * The loader keeps the arrays and interpolates trilinearly between cell
 * centres (the flight loop's air callback).
 */
#include "cfd_private.h"

#include <errno.h>
#include <hdf5.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

struct cfd_field {
    cfd_grid *g;
    double *var[CFD_NVARS];
    cfd_meta meta;
    double rho_kgpm3, nu_m2ps; /* 0 when the file does not say */
};

/* HDF5 attribute names of cfd_result.residual[], written and read alike */
static const char *const residual_names[5] = {"residual_continuity", "residual_u", "residual_v", "residual_w",
                                              "residual_k"};

static int attr_double(hid_t loc, const char *name, double v)
{
    hid_t sp = H5Screate(H5S_SCALAR);
    hid_t a = H5Acreate2(loc, name, H5T_NATIVE_DOUBLE, sp, H5P_DEFAULT, H5P_DEFAULT);
    herr_t rc = a >= 0 ? H5Awrite(a, H5T_NATIVE_DOUBLE, &v) : -1;
    if (a >= 0)
        H5Aclose(a);
    H5Sclose(sp);
    return rc < 0 ? -1 : 0;
}

static int attr_string(hid_t loc, const char *name, const char *v)
{
    hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, strlen(v) + 1);
    hid_t sp = H5Screate(H5S_SCALAR);
    hid_t a = H5Acreate2(loc, name, t, sp, H5P_DEFAULT, H5P_DEFAULT);
    herr_t rc = a >= 0 ? H5Awrite(a, t, v) : -1;
    if (a >= 0)
        H5Aclose(a);
    H5Sclose(sp);
    H5Tclose(t);
    return rc < 0 ? -1 : 0;
}

static int write_ds(hid_t loc, const char *name, hid_t type, int rank, const hsize_t *dims, const void *data)
{
    hid_t sp = H5Screate_simple(rank, dims, NULL);
    hid_t ds = H5Dcreate2(loc, name, type, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    herr_t rc = ds >= 0 ? H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) : -1;
    if (ds >= 0)
        H5Dclose(ds);
    H5Sclose(sp);
    return rc < 0 ? -1 : 0;
}

static void xmf_path(const char *path, char *out, size_t n)
{
    size_t len = strlen(path);
    if (len > 3 && strcmp(path + len - 3, ".h5") == 0)
        snprintf(out, n, "%.*s.xmf", (int)(len - 3), path);
    else
        snprintf(out, n, "%s.xmf", path);
}

static int write_xmf(const char *tmp, const char *h5name, const int n[3])
{
    FILE *f = fopen(tmp, "w");
    if (!f)
        return -1;
    fprintf(f, "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n");
    fprintf(f, "  <Grid Name=\"airwake\" GridType=\"Uniform\">\n");
    fprintf(f, "   <Information Name=\"frame\" Value=\"ship frame S: x bow, y starboard, z down (not flipped)\"/>\n");
    fprintf(f, "   <Topology TopologyType=\"3DRectMesh\" Dimensions=\"%d %d %d\"/>\n", n[2] + 1, n[1] + 1, n[0] + 1);
    fprintf(f, "   <Geometry GeometryType=\"VXVYVZ\">\n");
    const char *ax[3] = {"x", "y", "z"};
    for (int d = 0; d < 3; d++)
        fprintf(f,
                "    <DataItem Dimensions=\"%d\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">%s:/grid/%s_nodes</DataItem>\n",
                n[d] + 1, h5name, ax[d]);
    fprintf(f, "   </Geometry>\n");
    fprintf(f, "   <Attribute Name=\"velocity\" AttributeType=\"Vector\" Center=\"Cell\">\n");
    fprintf(f, "    <DataItem ItemType=\"Function\" Function=\"JOIN($0, $1, $2)\" Dimensions=\"%d %d %d 3\">\n", n[2],
            n[1], n[0]);
    for (int v = 0; v < 3; v++)
        fprintf(f,
                "     <DataItem Dimensions=\"%d %d %d\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">%s:/fields/%s</DataItem>\n",
                n[2], n[1], n[0], h5name, cfd_var_names[v]);
    fprintf(f, "    </DataItem>\n   </Attribute>\n");
    for (int v = 0; v < CFD_NVARS; v++)
        fprintf(f,
                "   <Attribute Name=\"%s\" AttributeType=\"Scalar\" Center=\"Cell\">\n    <DataItem Dimensions=\"%d %d %d\" "
                "NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">%s:/fields/%s</DataItem>\n   </Attribute>\n",
                cfd_var_names[v], n[2], n[1], n[0], h5name, cfd_var_names[v]);
    fprintf(f, "   <Attribute Name=\"solid\" AttributeType=\"Scalar\" Center=\"Cell\">\n    <DataItem Dimensions=\"%d %d %d\" "
               "NumberType=\"UChar\" Precision=\"1\" Format=\"HDF\">%s:/grid/solid</DataItem>\n   </Attribute>\n",
            n[2], n[1], n[0], h5name);
    fprintf(f, "  </Grid>\n </Domain>\n</Xdmf>\n");
    int bad = ferror(f);
    return (fclose(f) || bad) ? -1 : 0;
}

/* The checksum a field file carries in its data_crc64 attribute: the
 * nodes, the solid flags and every variable, as stored (little-endian
 * doubles on the machines disim runs on), CRC-64/XZ (core_crc64). */
static uint64_t field_crc(const cfd_grid *g, double *const *var)
{
    uint64_t c = 0;
    for (int d = 0; d < 3; d++)
        c = core_crc64(c, g->xn[d], ((size_t)g->n[d] + 1) * sizeof(double));
    c = core_crc64(c, g->solid, g->ncell);
    for (int v = 0; v < CFD_NVARS; v++)
        c = core_crc64(c, var[v], g->ncell * sizeof(double));
    return c;
}

/* The seal. A field file begins with HDF5's user block of SEAL_BYTES,
 * which HDF5 leaves to its user (the superblock follows it; HDF5 User's
 * Guide, "User block"), holding a text header, NUL-padded:
 *     disim airwake field
 *     bytes N
 *     crc64 HHHHHHHHHHHHHHHH
 * N the file's size and H the CRC-64/XZ of every byte after the user
 * block. The loader checks both before HDF5 reads a byte: a file cut
 * short, bit rot or a stray write is refused with its name, and libhdf5
 * (whose parser is not safe on a damaged file: docs/validation.md,
 * Fuzzing) never sees one. A file with HDF5's signature at its start (a
 * field written before fields were sealed) is read unsealed. */
#define SEAL_BYTES 512
static const char seal_magic[] = "disim airwake field\n";
static const unsigned char hdf5_sig[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};

/* CRC-64 of fp's bytes from SEAL_BYTES to its end, and their count: 0, or
 * -1 on a read error. */
static int crc_after_seal(FILE *fp, uint64_t *crc, uint64_t *bytes)
{
    return fseek(fp, SEAL_BYTES, SEEK_SET) != 0 || core_crc64_file(fp, crc, bytes) != 0 ? -1 : 0;
}

int cfd_field_seal(const char *path, core_err *err)
{
    FILE *fp = fopen(path, "r+b");
    if (!fp)
        return core_err_set(err, -1, "%s: cannot open to seal: %s", path, strerror(errno));
    unsigned char sig[8];
    uint64_t crc = 0, rest = 0;
    int rc = 0;
    if (fseek(fp, SEAL_BYTES, SEEK_SET) != 0 || fread(sig, 1, sizeof sig, fp) != sizeof sig ||
        memcmp(sig, hdf5_sig, sizeof sig) != 0)
        rc = core_err_set(err, -1, "%s: no HDF5 superblock after a user block of %d bytes: not a field cfd wrote",
                          path, SEAL_BYTES);
    else if (crc_after_seal(fp, &crc, &rest) != 0)
        rc = core_err_set(err, -1, "%s: read error while sealing", path);
    char head[SEAL_BYTES];
    memset(head, 0, sizeof head);
    snprintf(head, sizeof head, "%sbytes %llu\ncrc64 %016llx\n", seal_magic, (unsigned long long)rest + SEAL_BYTES,
             (unsigned long long)crc);
    if (!rc && (fseek(fp, 0, SEEK_SET) != 0 || fwrite(head, 1, sizeof head, fp) != sizeof head))
        rc = core_err_set(err, -1, "%s: cannot write its seal: %s", path, strerror(errno));
    if (fclose(fp) != 0 && !rc)
        rc = core_err_set(err, -1, "%s: cannot write its seal: %s", path, strerror(errno));
    return rc;
}

/* The seal of the file at path (size bytes) checked: 1 sealed and whole,
 * 0 unsealed (HDF5's signature at its start), < 0 with err. */
static int seal_check(const char *path, unsigned long long size, core_err *err)
{
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return core_err_set(err, -1, "%s: cannot open: %s", path, strerror(errno));
    char head[SEAL_BYTES + 1];
    size_t got = fread(head, 1, SEAL_BYTES, fp);
    head[got] = '\0';
    int rc;
    unsigned long long want_bytes = 0, want_crc = 0;
    uint64_t crc = 0, bytes = 0;
    int used = 0;
    if (got >= sizeof hdf5_sig && memcmp(head, hdf5_sig, sizeof hdf5_sig) == 0)
        rc = 0;
    else if (got < sizeof seal_magic - 1 || memcmp(head, seal_magic, sizeof seal_magic - 1) != 0)
        rc = core_err_set(err, -1, "%s: not an HDF5 file (neither a disim field's header nor HDF5's signature at "
                                   "its start)", path);
    else if (sscanf(head + sizeof seal_magic - 1, "bytes %llu\ncrc64 %16llx\n%n", &want_bytes, &want_crc, &used) != 2 ||
             used == 0)
        rc = core_err_set(err, -1, "%s: a damaged field header (expected 'bytes N' and 'crc64 H' after '%.19s')",
                          path, seal_magic);
    else if (want_bytes != size)
        rc = core_err_set(err, -1, "%s: %llu bytes, its header says %llu: cut short or written past its end "
                                   "(a damaged field; build it again)", path, size, want_bytes);
    else if (crc_after_seal(fp, &crc, &bytes) != 0)
        rc = core_err_set(err, -1, "%s: read error while checking its seal", path);
    else if (crc != want_crc || bytes + SEAL_BYTES != size)
        rc = core_err_set(err, -1, "%s: the file does not match its checksum (crc64 %016llx in its header, the file "
                                   "gives %016llx): a damaged field, build it again", path, want_crc,
                          (unsigned long long)crc);
    else
        rc = 1;
    fclose(fp);
    return rc;
}

/* The whole file, from either a solver or a loaded field: grid, arrays,
 * optional residual history (nh rows), metadata. */
static int write_field(const cfd_grid *g, double *const *var, const double *hist, int nh, double rho,
                       double nu, const cfd_meta *meta, const char *path, core_err *err)
{
    for (int v = 0; v < CFD_NVARS; v++)
        for (size_t c = 0; c < g->ncell; c++)
            if (!isfinite(var[v][c]))
                return core_err_set(err, -1, "%s: not written: the field holds NaN or infinite values", path);
    char tmp[4200], xmf[4100], xtmp[4200];
    if (strlen(path) > 4000)
        return core_err_set(err, -1, "%.64s...: output path too long", path);
    snprintf(tmp, sizeof tmp, "%s.tmp.%ld", path, (long)getpid());
    xmf_path(path, xmf, sizeof xmf);
    snprintf(xtmp, sizeof xtmp, "%s.tmp.%ld", xmf, (long)getpid());
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    hid_t fcpl = H5Pcreate(H5P_FILE_CREATE);
    if (fcpl < 0 || H5Pset_userblock(fcpl, SEAL_BYTES) < 0) {
        if (fcpl >= 0)
            H5Pclose(fcpl);
        return core_err_set(err, -1, "%s: cannot create (HDF5: the user block)", tmp);
    }
    hid_t f = H5Fcreate(tmp, H5F_ACC_TRUNC, fcpl, H5P_DEFAULT);
    H5Pclose(fcpl);
    if (f < 0)
        return core_err_set(err, -1, "%s: cannot create (HDF5)", tmp);
    int rc = 0;
    hid_t gg = H5Gcreate2(f, "grid", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    hid_t gf = H5Gcreate2(f, "fields", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (gg < 0 || gf < 0)
        rc = -1;
    const char *nn[3] = {"x_nodes", "y_nodes", "z_nodes"};
    for (int d = 0; d < 3 && !rc; d++) {
        hsize_t dim = (hsize_t)g->n[d] + 1;
        rc |= write_ds(gg, nn[d], H5T_NATIVE_DOUBLE, 1, &dim, g->xn[d]);
    }
    hsize_t dims[3] = {(hsize_t)g->n[2], (hsize_t)g->n[1], (hsize_t)g->n[0]};
    if (!rc)
        rc |= write_ds(gg, "solid", H5T_NATIVE_UCHAR, 3, dims, g->solid);
    for (int v = 0; v < CFD_NVARS && !rc; v++)
        rc |= write_ds(gf, cfd_var_names[v], H5T_NATIVE_DOUBLE, 3, dims, var[v]);
    if (!rc && hist && nh > 0) {
        hsize_t hd[2] = {(hsize_t)nh, 5};
        rc |= write_ds(f, "residuals", H5T_NATIVE_DOUBLE, 2, hd, hist);
    }
    if (!rc) {
        rc |= attr_string(f, "solver_version", CFD_VERSION);
        rc |= attr_string(f, "engine", meta->engine[0] ? meta->engine : "embedded");
        rc |= attr_string(f, "engine_version", meta->engine[0] ? meta->engine_version : CFD_VERSION);
        rc |= attr_double(f, "monitor_change", meta->result.monitor_change);
        if (meta->rotor_model[0]) {
            rc |= attr_string(f, "rotor_model", meta->rotor_model);
            rc |= attr_double(f, "rotor_force_N", meta->rotor_force_N);
            rc |= attr_double(f, "rotor_torque_Nm", meta->rotor_torque_Nm);
        }
        char crc[24];
        snprintf(crc, sizeof crc, "%016llx", (unsigned long long)field_crc(g, var));
        rc |= attr_string(f, "data_crc64", crc);
        rc |= attr_string(f, "frame", "ship frame S: x bow, y starboard, z down; SI units; p in Pa gauge");
        rc |= attr_string(f, "ship", meta->ship);
        rc |= attr_string(f, "rotor", meta->rotor);
        rc |= attr_string(f, "grid_level", meta->grid);
        rc |= attr_double(f, "wod_speed_mps", meta->wod_speed_mps);
        rc |= attr_double(f, "wod_dir_deg", meta->wod_dir_deg);
        rc |= attr_double(f, "rotor_thrust_N", meta->rotor_thrust_N);
        rc |= attr_double(f, "rotor_radius_m", meta->rotor_radius_m);
        for (int q = 0; q < 3; q++) {
            char nm[32];
            snprintf(nm, sizeof nm, "rotor_centre_S_m_%c", 'x' + q);
            rc |= attr_double(f, nm, meta->rotor_centre_S_m[q]);
        }
        rc |= attr_double(f, "iterations", meta->result.iterations);
        rc |= attr_double(f, "converged", meta->result.converged);
        rc |= attr_double(f, "averaged_iterations", meta->result.averaged);
        rc |= attr_double(f, "steady_mean", meta->result.steady_mean);
        rc |= attr_double(f, "mean_drift", meta->result.mean_drift);
        rc |= attr_double(f, "mean_change", meta->result.mean_change);
        rc |= attr_double(f, "wall_time_s", meta->result.wall_s);
        rc |= attr_double(f, "mirrored", meta->mirrored);
        for (int q = 0; q < 5; q++)
            rc |= attr_double(f, residual_names[q], meta->result.residual[q]);
        rc |= attr_double(f, "rho_kgpm3", rho);
        rc |= attr_double(f, "nu_m2ps", nu);
    }
    if (gg >= 0)
        H5Gclose(gg);
    if (gf >= 0)
        H5Gclose(gf);
    if (H5Fclose(f) < 0)
        rc = -1;
    if (rc) {
        unlink(tmp);
        return core_err_set(err, -1, "%s: HDF5 write failed", tmp);
    }
    if (cfd_field_seal(tmp, err) != 0) {
        unlink(tmp);
        return -1;
    }
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    if (write_xmf(xtmp, base, g->n)) {
        unlink(tmp);
        unlink(xtmp);
        return core_err_set(err, -1, "%s: cannot write the XDMF file", xtmp);
    }
    /* The field on disk before its name is (a rename after a power cut
     * must not expose a file still in the page cache). */
    if (core_sync_path(tmp) != 0) {
        int e = errno;
        unlink(tmp);
        unlink(xtmp);
        return core_err_set(err, -1, "%s: cannot sync: %s", tmp, strerror(e));
    }
    /* The side file names the field's dimensions: an old one must not
     * outlive its field, so it goes before the new field takes the name,
     * and a failure between the two renames leaves a field without a
     * side file, never one with a wrong side file. */
    if (unlink(xmf) != 0 && errno != ENOENT) {
        int e = errno;
        unlink(tmp);
        unlink(xtmp);
        return core_err_set(err, -1, "%s: cannot replace: %s (the field is not written)", xmf, strerror(e));
    }
    if (rename(tmp, path) != 0) {
        int e = errno;
        unlink(tmp);
        unlink(xtmp);
        return core_err_set(err, -1, "%s: cannot rename %s into place: %s", path, tmp, strerror(e));
    }
    if (rename(xtmp, xmf) != 0) {
        int e = errno;
        unlink(xtmp);
        return core_err_set(err, -1, "%s: cannot rename %s into place: %s (%s is written)", xmf, xtmp, strerror(e),
                            path);
    }
    return 0;
}

int cfd_solver_write(const cfd_solver *s, const cfd_meta *meta, const char *path, core_err *err)
{
    double *var[CFD_NVARS];
    for (int v = 0; v < CFD_NVARS; v++)
        var[v] = (double *)cfd_solver_var(s, v);
    int nh = 0;
    const double *hist = cfd_solver_history(s, &nh);
    return write_field(cfd_solver_grid(s), var, hist, nh, cfd_solver_config(s)->rho_kgpm3,
                       cfd_solver_config(s)->nu_m2ps, meta, path, err);
}

int cfd_field_write(const cfd_field *f, const char *path, core_err *err)
{
    return write_field(f->g, f->var, NULL, 0, f->rho_kgpm3, f->nu_m2ps, &f->meta, path, err);
}

/* ------------------------------------------------------------------ loader */
/* One number from an attribute: 0, 1 if absent and optional, < 0 (err names
 * the attribute) if absent and required, not one number, or not finite.
 * H5Aread fills as many values as the attribute holds, so an array here
 * would overrun v: the extent is checked first. */
static int read_attr_double(hid_t f, const char *path, const char *name, int required, double *v,
                            core_err *err)
{
    htri_t ex = H5Aexists(f, name);
    if (ex == 0 && !required)
        return 1;
    if (ex <= 0)
        return core_err_set(err, -1, "%s: attribute %s missing (not a disim airwake field, or a damaged one)",
                            path, name);
    hid_t a = H5Aopen(f, name, H5P_DEFAULT);
    if (a < 0)
        return core_err_set(err, -1, "%s: attribute %s cannot be read (corrupt file?)", path, name);
    hid_t sp = H5Aget_space(a), t = H5Aget_type(a);
    hssize_t np = sp >= 0 ? H5Sget_simple_extent_npoints(sp) : -1;
    H5T_class_t cls = t >= 0 ? H5Tget_class(t) : H5T_NO_CLASS;
    double x = 0.0;
    herr_t rc = -1;
    /* a number of at most 8 bytes: HDF5 would convert through a buffer of
     * the size a damaged type declares */
    size_t tsz = t >= 0 ? H5Tget_size(t) : 0;
    if (np == 1 && (cls == H5T_FLOAT || cls == H5T_INTEGER) && tsz >= 1 && tsz <= 8)
        rc = H5Aread(a, H5T_NATIVE_DOUBLE, &x);
    if (t >= 0)
        H5Tclose(t);
    if (sp >= 0)
        H5Sclose(sp);
    H5Aclose(a);
    if (rc < 0)
        return core_err_set(err, -1, "%s: attribute %s: expected one number", path, name);
    if (!isfinite(x))
        return core_err_set(err, -1, "%s: attribute %s is %g: expected a finite number", path, name, x);
    *v = x;
    return 0;
}

/* One fixed-length string from an attribute into out (size n): 0, or < 0
 * (err names the attribute) if absent, not one string, or too long for out
 * (a cut name would match another ship's or grid's). */
static int read_attr_string(hid_t f, const char *path, const char *name, char *out, size_t n, core_err *err)
{
    out[0] = 0;
    if (H5Aexists(f, name) <= 0)
        return core_err_set(err, -1, "%s: attribute %s missing (not a disim airwake field, or a damaged one)",
                            path, name);
    hid_t a = H5Aopen(f, name, H5P_DEFAULT);
    if (a < 0)
        return core_err_set(err, -1, "%s: attribute %s cannot be read (corrupt file?)", path, name);
    hid_t sp = H5Aget_space(a), t = H5Aget_type(a);
    hssize_t np = sp >= 0 ? H5Sget_simple_extent_npoints(sp) : -1;
    int ok = np == 1 && t >= 0 && H5Tget_class(t) == H5T_STRING && H5Tis_variable_str(t) == 0;
    size_t sz = ok ? H5Tget_size(t) : 0;
    /* disim writes the string's length + 1: a longer type (a damaged one
     * declares gigabytes) is refused before its buffer is allocated */
    int rc = ok && sz > n ? -2 : -1;
    char *buf = ok && rc == -1 ? calloc(sz + 1, 1) : NULL;
    if (buf) {
        hid_t mt = H5Tcopy(H5T_C_S1);
        if (mt >= 0 && H5Tset_size(mt, sz) >= 0 && H5Aread(a, mt, buf) >= 0)
            rc = strlen(buf) < n ? 0 : -2;
        if (mt >= 0)
            H5Tclose(mt);
    }
    if (rc == 0)
        memcpy(out, buf, strlen(buf) + 1);
    free(buf);
    if (t >= 0)
        H5Tclose(t);
    if (sp >= 0)
        H5Sclose(sp);
    H5Aclose(a);
    if (rc == -2)
        return core_err_set(err, -1, "%s: attribute %s: longer than %zu characters", path, name, n - 1);
    if (rc < 0)
        return core_err_set(err, -1, "%s: attribute %s: expected one fixed-length string", path, name);
    return 0;
}

/* Open a dataset and check its rank and extent (slowest dimension first)
 * against what the grid expects: the element count alone would pass a field
 * stored nx x ny x nz for a grid's nz x ny x nx, read transposed. dims[d] 0
 * accepts any extent and returns it there. Its stored type must be the one
 * disim writes (class cls, size bytes): HDF5 converts through a buffer of
 * the size a damaged type declares. The dataset, or -1 with err set. */
static hid_t open_ds(hid_t f, const char *path, const char *name, int rank, hsize_t *dims, H5T_class_t cls,
                     size_t size, core_err *err)
{
    if (H5Lexists(f, name, H5P_DEFAULT) <= 0) {
        core_err_set(err, -1, "%s: dataset %s missing (not a disim airwake field, or a damaged one)", path, name);
        return -1;
    }
    hid_t ds = H5Dopen2(f, name, H5P_DEFAULT);
    if (ds < 0) {
        core_err_set(err, -1, "%s: %s cannot be opened as a dataset (corrupt file?)", path, name);
        return -1;
    }
    hid_t sp = H5Dget_space(ds);
    int r = sp >= 0 ? H5Sget_simple_extent_ndims(sp) : -1;
    hsize_t got[3] = {0, 0, 0};
    int ok = r >= 1 && r <= 3 && H5Sget_simple_extent_dims(sp, got, NULL) == r && r == rank;
    for (int d = 0; ok && d < rank; d++)
        ok = dims[d] == 0 || got[d] == dims[d];
    if (sp >= 0)
        H5Sclose(sp);
    if (!ok) {
        char want[96] = "", have[96] = "";
        for (int d = 0; d < rank; d++) {
            size_t lw = strlen(want);
            snprintf(want + lw, sizeof want - lw, dims[d] ? "%s%llu" : "%s*", d ? " x " : "",
                     (unsigned long long)dims[d]);
        }
        for (int d = 0; r > 0 && r <= 3 && d < r; d++) {
            size_t lh = strlen(have);
            snprintf(have + lh, sizeof have - lh, "%s%llu", d ? " x " : "", (unsigned long long)got[d]);
        }
        core_err_set(err, -1, "%s: %s has extent %s (rank %d), expected %s", path, name, r > 0 && r <= 3 ? have : "?",
                     r, want);
        H5Dclose(ds);
        return -1;
    }
    hid_t t = H5Dget_type(ds);
    H5T_class_t tc = t >= 0 ? H5Tget_class(t) : H5T_NO_CLASS;
    size_t tsz = t >= 0 ? H5Tget_size(t) : 0;
    if (t >= 0)
        H5Tclose(t);
    if (tc != cls || tsz != size) {
        core_err_set(err, -1, "%s: %s is stored as %s of %zu bytes, expected %s of %zu bytes", path, name,
                     tc == H5T_FLOAT ? "floats" : tc == H5T_INTEGER ? "integers" : "another type", tsz,
                     cls == H5T_FLOAT ? "floats" : "integers", size);
        H5Dclose(ds);
        return -1;
    }
    /* the data the extent calls for must be stored: HDF5 1.10.8 reads a
     * damaged dataset's short storage past its own buffer */
    unsigned long long need = size;
    for (int d = 0; d < rank; d++)
        need = got[d] && need > ULLONG_MAX / got[d] ? ULLONG_MAX : need * got[d];
    unsigned long long have = (unsigned long long)H5Dget_storage_size(ds);
    if (have < need) {
        core_err_set(err, -1, "%s: %s holds %llu bytes, its extent needs %llu (a truncated or damaged field)", path,
                     name, have, need);
        H5Dclose(ds);
        return -1;
    }
    for (int d = 0; d < rank; d++)
        dims[d] = got[d];
    return ds;
}

/* Read a dataset opened and checked by open_ds, then closed. */
static int read_ds(hid_t ds, const char *path, const char *name, hid_t type, void *out, core_err *err)
{
    herr_t rc = H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out);
    H5Dclose(ds);
    if (rc < 0)
        return core_err_set(err, -1, "%s: %s cannot be read (truncated or corrupt file?)", path, name);
    return 0;
}

cfd_field *cfd_field_load(const char *path, core_err *err)
{
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    struct stat st;
    if (stat(path, &st) != 0) {
        core_err_set(err, -1, "%s: cannot open: %s", path, strerror(errno));
        return NULL;
    }
    if (core_file_check_stat(path, &st, -1, err) != 0)
        return NULL;
    if (access(path, R_OK)) {
        core_err_set(err, -1, "%s: cannot read the file", path);
        return NULL;
    }
    int sealed = seal_check(path, (unsigned long long)st.st_size, err);
    if (sealed < 0)
        return NULL;
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    if (f < 0) {
        /* the signature is at the start: a file cut short still has it */
        if (H5Fis_hdf5(path) > 0)
            core_err_set(err, -1, "%s: HDF5 file that cannot be opened (truncated or corrupt)", path);
        else
            core_err_set(err, -1, "%s: not an HDF5 file", path);
        return NULL;
    }
    cfd_field *fl = NULL;
    double *xn[3] = {NULL, NULL, NULL};
    hid_t nds[3] = {-1, -1, -1};
    int n[3];
    const char *nn[3] = {"/grid/x_nodes", "/grid/y_nodes", "/grid/z_nodes"};
    /* all three extents before any allocation: the cell count and the
     * arrays' bytes must fit an int per axis and a size_t in all */
    size_t nc = 1;
    if (H5Lexists(f, "/grid", H5P_DEFAULT) <= 0 || H5Lexists(f, "/fields", H5P_DEFAULT) <= 0) {
        core_err_set(err, -1, "%s: group /grid or /fields missing (not a disim airwake field)", path);
        goto fail;
    }
    /* what the extents call for must be in the file (the nodes, the solid
     * mask and every variable, uncompressed): a damaged header declaring a
     * billion nodes is refused here, not by an allocation of gigabytes */
    const unsigned long long fsize = (unsigned long long)st.st_size, per_cell = 1 + CFD_NVARS * sizeof(double);
    unsigned long long need = 0;
    for (int d = 0; d < 3; d++) {
        hsize_t np = 0;
        if ((nds[d] = open_ds(f, path, nn[d], 1, &np, H5T_FLOAT, sizeof(double), err)) < 0)
            goto fail;
        if (np < 2 || np - 1 > (hsize_t)INT_MAX) {
            core_err_set(err, -1, "%s: %s has %llu nodes: expected 2 to %d", path, nn[d], (unsigned long long)np,
                         INT_MAX);
            goto fail;
        }
        n[d] = (int)(np - 1);
        need += (unsigned long long)np * sizeof(double);
        if (need > fsize || (size_t)n[d] > fsize / per_cell / nc) {
            core_err_set(err, -1, "%s: grid of %d x %d x %d cells: its data need more than the file's %llu bytes "
                                  "(a truncated or damaged field)", path, n[0], d > 0 ? n[1] : 1, d > 1 ? n[2] : 1,
                         fsize);
            goto fail;
        }
        nc *= (size_t)n[d];
    }
    for (int d = 0; d < 3; d++) {
        xn[d] = malloc(((size_t)n[d] + 1) * sizeof(double));
        if (!xn[d]) {
            core_err_set(err, -2, "%s: out of memory", path);
            goto fail;
        }
        hid_t ds = nds[d];
        nds[d] = -1;
        if (read_ds(ds, path, nn[d], H5T_NATIVE_DOUBLE, xn[d], err))
            goto fail;
        /* the grid refuses nodes that do not increase, NaN among them; an
         * infinite end node would still increase */
        for (int i = 0; i <= n[d]; i++)
            if (!isfinite(xn[d][i])) {
                core_err_set(err, -1, "%s: %s node %d is %g: expected a finite coordinate", path, nn[d], i,
                             xn[d][i]);
                goto fail;
            }
    }
    fl = calloc(1, sizeof *fl);
    if (!fl) {
        core_err_set(err, -2, "%s: out of memory", path);
        goto fail;
    }
    core_err gerr = {0};
    fl->g = cfd_grid_create(xn[0], n[0], xn[1], n[1], xn[2], n[2], &gerr);
    if (!fl->g) {
        /* the grid's message does not know the file */
        core_err_set(err, -1, "%s: %s", path, gerr.msg);
        goto fail;
    }
    hsize_t cells[3] = {(hsize_t)n[2], (hsize_t)n[1], (hsize_t)n[0]};
    hid_t ds = open_ds(f, path, "/grid/solid", 3, cells, H5T_INTEGER, 1, err);
    if (ds < 0 || read_ds(ds, path, "/grid/solid", H5T_NATIVE_UCHAR, fl->g->solid, err))
        goto fail;
    for (int v = 0; v < CFD_NVARS; v++) {
        char name[64];
        snprintf(name, sizeof name, "/fields/%s", cfd_var_names[v]);
        fl->var[v] = malloc(nc * sizeof(double));
        if (!fl->var[v]) {
            core_err_set(err, -2, "%s: out of memory", path);
            goto fail;
        }
        if ((ds = open_ds(f, path, name, 3, cells, H5T_FLOAT, sizeof(double), err)) < 0 ||
            read_ds(ds, path, name, H5T_NATIVE_DOUBLE, fl->var[v], err))
            goto fail;
        for (size_t c = 0; c < nc; c++)
            if (!isfinite(fl->var[v][c])) {
                core_err_set(err, -1, "%s: %s holds a NaN or infinity at cell %zu", path, name, c);
                goto fail;
            }
    }
    /* What names the field and what its users act on has been written since
     * the first solver; the rest is absent in older fields or informative. */
    cfd_meta *m = &fl->meta;
    double it = 0, conv = 0, avg = 0, steady = 0, mir = 0.0;
    m->result.mean_change = -1.0;
    if (read_attr_string(f, path, "ship", m->ship, sizeof m->ship, err) ||
        read_attr_string(f, path, "rotor", m->rotor, sizeof m->rotor, err) ||
        read_attr_string(f, path, "grid_level", m->grid, sizeof m->grid, err) ||
        read_attr_double(f, path, "wod_speed_mps", 1, &m->wod_speed_mps, err) ||
        read_attr_double(f, path, "wod_dir_deg", 1, &m->wod_dir_deg, err) ||
        read_attr_double(f, path, "rotor_thrust_N", 1, &m->rotor_thrust_N, err) ||
        read_attr_double(f, path, "rotor_radius_m", 1, &m->rotor_radius_m, err) ||
        read_attr_double(f, path, "iterations", 1, &it, err) ||
        read_attr_double(f, path, "converged", 1, &conv, err) ||
        /* absent in fields before solver 0.2.1 */
        read_attr_double(f, path, "averaged_iterations", 0, &avg, err) < 0 ||
        /* absent before solver 0.4.0 */
        read_attr_double(f, path, "steady_mean", 0, &steady, err) < 0 ||
        read_attr_double(f, path, "mean_drift", 0, &m->result.mean_drift, err) < 0 ||
        /* absent before solver 0.5.0 (-1: not known) */
        read_attr_double(f, path, "mean_change", 0, &m->result.mean_change, err) < 0 ||
        read_attr_double(f, path, "wall_time_s", 0, &m->result.wall_s, err) < 0 ||
        /* absent in fields not mirrored by earlier builds */
        read_attr_double(f, path, "mirrored", 0, &mir, err) < 0 ||
        read_attr_double(f, path, "rho_kgpm3", 0, &fl->rho_kgpm3, err) < 0 ||
        read_attr_double(f, path, "nu_m2ps", 0, &fl->nu_m2ps, err) < 0)
        goto fail;
    for (int q = 0; q < 5; q++)
        if (read_attr_double(f, path, residual_names[q], 0, &m->result.residual[q], err) < 0)
            goto fail;
    /* absent in fields before the engine was recorded: the embedded solver's */
    if (read_attr_double(f, path, "monitor_change", 0, &m->result.monitor_change, err) < 0)
        goto fail;
    snprintf(m->engine, sizeof m->engine, "embedded");
    snprintf(m->engine_version, sizeof m->engine_version, "%s", CFD_VERSION);
    if ((H5Aexists(f, "engine") > 0 && read_attr_string(f, path, "engine", m->engine, sizeof m->engine, err)) ||
        (H5Aexists(f, "engine_version") > 0 &&
         read_attr_string(f, path, "engine_version", m->engine_version, sizeof m->engine_version, err)))
        goto fail;
    /* absent but for a rotor the engine built its own way */
    if ((H5Aexists(f, "rotor_model") > 0 &&
         read_attr_string(f, path, "rotor_model", m->rotor_model, sizeof m->rotor_model, err)) ||
        read_attr_double(f, path, "rotor_force_N", 0, &m->rotor_force_N, err) < 0 ||
        read_attr_double(f, path, "rotor_torque_Nm", 0, &m->rotor_torque_Nm, err) < 0)
        goto fail;
    /* the rotor's centre, written with the thrust and radius (a reader
     * that writes the field again, or mirrors it, keeps it) */
    for (int q = 0; q < 3; q++) {
        char nm[32];
        snprintf(nm, sizeof nm, "rotor_centre_S_m_%c", 'x' + q);
        if (read_attr_double(f, path, nm, 0, &m->rotor_centre_S_m[q], err) < 0)
            goto fail;
    }
    /* counts become ints: a value past INT_MAX would not convert */
    const char *bad = !(m->wod_speed_mps >= 0.0) ? "wod_speed_mps"
                      : !(m->rotor_radius_m >= 0.0) ? "rotor_radius_m"
                      : !(it >= 0.0 && it <= INT_MAX) ? "iterations"
                      : !(avg >= 0.0 && avg <= INT_MAX) ? "averaged_iterations"
                      : !(fl->rho_kgpm3 >= 0.0) ? "rho_kgpm3"
                      : !(fl->nu_m2ps >= 0.0) ? "nu_m2ps"
                                               : NULL;
    if (bad) {
        core_err_set(err, -1, "%s: attribute %s out of range (negative or too large)", path, bad);
        goto fail;
    }
    m->result.iterations = (int)it;
    m->result.converged = conv != 0.0;
    m->result.averaged = (int)avg;
    m->result.steady_mean = steady != 0.0;
    m->mirrored = mir != 0.0;
    /* the data's checksum: a field overwritten with finite garbage is
     * refused; a field written before files carried one is read (its
     * meta.checksum 0), as the database checks its own files' CRCs */
    if (H5Aexists(f, "data_crc64") > 0) {
        char want[32];
        if (read_attr_string(f, path, "data_crc64", want, sizeof want, err))
            goto fail;
        char got[24];
        snprintf(got, sizeof got, "%016llx", (unsigned long long)field_crc(fl->g, fl->var));
        if (strcmp(want, got) != 0) {
            core_err_set(err, -1, "%s: the data do not match the file's checksum (data_crc64 %s, the data give %s): "
                                  "a damaged field, build it again", path, want, got);
            goto fail;
        }
        m->checksum = 1;
    }
    m->sealed = sealed;
    for (int d = 0; d < 3; d++)
        free(xn[d]);
    H5Fclose(f);
    return fl;
fail:
    for (int d = 0; d < 3; d++) {
        free(xn[d]);
        if (nds[d] >= 0)
            H5Dclose(nds[d]);
    }
    cfd_field_destroy(fl);
    H5Fclose(f);
    return NULL;
}

void cfd_field_destroy(cfd_field *f)
{
    if (!f)
        return;
    for (int v = 0; v < CFD_NVARS; v++)
        free(f->var[v]);
    cfd_grid_destroy(f->g);
    free(f);
}

int cfd_field_sample(const cfd_field *f, const double pos[3], double out[CFD_NVARS])
{
    cfd_sample_arrays(f->g, (double *const *)f->var, CFD_NVARS, pos, out);
    int outside = 0;
    for (int d = 0; d < 3; d++)
        outside |= pos[d] < f->g->xn[d][0] || pos[d] > f->g->xn[d][f->g->n[d]];
    return outside;
}

int cfd_field_sample_vars(const cfd_field *f, const double pos[3], const int *vars, int nvar, double *out)
{
    double *arr[CFD_NVARS];
    if (nvar < 0 || nvar > CFD_NVARS)
        return -1;
    for (int i = 0; i < nvar; i++) {
        if (vars[i] < 0 || vars[i] >= CFD_NVARS)
            return -1;
        arr[i] = f->var[vars[i]];
    }
    cfd_sample_arrays(f->g, arr, nvar, pos, out);
    int outside = 0;
    for (int d = 0; d < 3; d++)
        outside |= pos[d] < f->g->xn[d][0] || pos[d] > f->g->xn[d][f->g->n[d]];
    return outside;
}

int cfd_field_air(void *user, const double pos[3], double t_s, double vel[3])
{
    (void)t_s; /* a steady field */
    const cfd_field *f = user;
    double out[3];
    cfd_sample_arrays(f->g, (double *const *)f->var, 3, pos, out);
    int rc = 0;
    for (int d = 0; d < 3; d++)
        rc |= pos[d] < f->g->xn[d][0] || pos[d] > f->g->xn[d][f->g->n[d]];
    vel[0] = out[0];
    vel[1] = out[1];
    vel[2] = out[2];
    return rc;
}

int cfd_field_air_scaled(void *user, const double pos[3], double t_s, double vel[3])
{
    const cfd_field_scaled *a = user;
    int rc = cfd_field_air((void *)a->field, pos, t_s, vel);
    for (int d = 0; d < 3; d++)
        vel[d] *= a->scale;
    return rc;
}

const cfd_meta *cfd_field_meta(const cfd_field *f) { return &f->meta; }
void cfd_field_dims(const cfd_field *f, int n[3]) { cfd_grid_dims(f->g, n); }

cfd_field *cfd_field_mirror_y(const cfd_field *src, core_err *err)
{
    if (strcmp(src->meta.rotor, "off")) {
        /* a rotor's mirror image turns the other way: not the same aircraft */
        core_err_set(err, -1, "cfd field mirror: the field has a rotor (%s); only ship-only fields mirror",
                     src->meta.rotor);
        return NULL;
    }
    const cfd_grid *g = src->g;
    const int nx = g->n[0], ny = g->n[1], nz = g->n[2];
    double *yn = malloc((size_t)(ny + 1) * sizeof *yn);
    if (!yn) {
        core_err_set(err, -2, "cfd field mirror: out of memory");
        return NULL;
    }
    /* node j of the image is the mirror of node ny - j: ascending again */
    for (int j = 0; j <= ny; j++)
        yn[j] = -g->xn[1][ny - j];
    cfd_field *m = calloc(1, sizeof *m);
    if (!m) {
        free(yn);
        core_err_set(err, -2, "cfd field mirror: out of memory");
        return NULL;
    }
    m->g = cfd_grid_create(g->xn[0], nx, yn, ny, g->xn[2], nz, err);
    free(yn);
    if (!m->g) {
        cfd_field_destroy(m);
        return NULL;
    }
    for (int v = 0; v < CFD_NVARS; v++)
        if (!(m->var[v] = malloc(g->ncell * sizeof(double)))) {
            cfd_field_destroy(m);
            core_err_set(err, -2, "cfd field mirror: out of memory");
            return NULL;
        }
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++) {
                size_t to = CFD_IDX(g, i, j, k), from = CFD_IDX(g, i, ny - 1 - j, k);
                m->g->solid[to] = g->solid[from];
                for (int v = 0; v < CFD_NVARS; v++)
                    m->var[v][to] = v == CFD_VAR_V ? -src->var[v][from] : src->var[v][from];
            }
    m->meta = src->meta;
    m->meta.wod_dir_deg = core_wod_mirror_deg(src->meta.wod_dir_deg);
    m->meta.rotor_centre_S_m[1] = -src->meta.rotor_centre_S_m[1];
    m->meta.mirrored = 1;
    m->rho_kgpm3 = src->rho_kgpm3;
    m->nu_m2ps = src->nu_m2ps;
    return m;
}
