/*
 * rows.c: a job of exact 3D form factors with occlusion split into two row ranges through
 * the C API, run by `scripts/capi.sh check` under AddressSanitizer.
 *
 *   rows SCENE.vs3 TOLERANCE SPLIT DIR
 *
 * Computes rows 0..SPLIT (one thread) and SPLIT..n (two threads) of SCENE, writes them to
 * DIR/c0.sir and DIR/c1.sir, reads them back, merges them (in reverse order), measures the
 * merged job and checks it against si_measure_exact of the whole scene bit for bit: every
 * entry of F, its error estimate and the channel measures. Checks the failures on the way
 * (an empty or too long range, a merge of overlapping or of different jobs' rows, rows
 * missing, a corrupt or foreign file, a short buffer). Then prints the merged entries as
 * `i,j,F_ij,error` for capi.sh to compare with `sceneinfo merge P0.sir P1.sir --out F.ijv`
 * of the CLI's own ranges (and the C files with the CLI's, byte for byte).
 */
#include <sceneinfo.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failures = 0;

#define CHECK(cond)                                                                  \
    do {                                                                             \
        if (!(cond)) {                                                               \
            fprintf(stderr, "rows.c:%d: check failed: %s (last error: %s)\n",        \
                    __LINE__, #cond, si_error_message());                            \
            failures++;                                                              \
        }                                                                            \
    } while (0)

/* The last error's message contains `part`. */
static int says(const char *part) { return strstr(si_error_message(), part) != NULL; }

/* A measurement's sparse F and error estimates, and its measures. */
typedef struct {
    size_t n, nnz;
    size_t *row_ptr, *cols;
    double *vals, *errs;
    SiMeasures measures;
} Sparse;

static Sparse sparse_of(const SiMeasurement *m) {
    Sparse s = {0};
    s.n = si_measurement_n_states(m);
    CHECK(si_measurement_form_factors_csr(m, NULL, 0, NULL, NULL, 0, &s.nnz) ==
          SI_ERR_BUFFER_TOO_SMALL);
    s.row_ptr = malloc((s.n + 1) * sizeof(size_t));
    s.cols = malloc(s.nnz * sizeof(size_t));
    s.vals = malloc(s.nnz * sizeof(double));
    s.errs = malloc(s.nnz * sizeof(double));
    CHECK(si_measurement_form_factors_csr(m, s.row_ptr, s.n + 1, s.cols, s.vals, s.nnz,
                                          &s.nnz) == SI_OK);
    CHECK(si_measurement_form_factor_errors_csr(m, s.errs, s.nnz, NULL) == SI_OK);
    CHECK(si_measurement_measures(m, &s.measures) == SI_OK);
    return s;
}

static void sparse_free(Sparse *s) {
    free(s->row_ptr);
    free(s->cols);
    free(s->vals);
    free(s->errs);
}

/* Same bits (NaN estimates of the background state's entries included). */
static int same_bits(const void *a, const void *b, size_t bytes) {
    return bytes == 0 || memcmp(a, b, bytes) == 0;
}

int main(int argc, char **argv) {
    if (argc != 5) {
        fprintf(stderr, "usage: rows SCENE.vs3 TOLERANCE SPLIT DIR\n");
        return 2;
    }
    const double tol = strtod(argv[2], NULL);
    const size_t split = (size_t)strtoul(argv[3], NULL, 10);
    char p0[4096], p1[4096], bad[4096];
    snprintf(p0, sizeof p0, "%s/c0.sir", argv[4]);
    snprintf(p1, sizeof p1, "%s/c1.sir", argv[4]);
    snprintf(bad, sizeof bad, "%s/corrupt.sir", argv[4]);

    SiScene *scene = NULL;
    CHECK(si_scene_from_file(argv[1], SI_FORMAT_AUTO, &scene) == SI_OK);
    if (scene == NULL) return 1;
    const size_t n = si_scene_n_patches(scene);
    CHECK(split > 0 && split < n);

    /* Ranges refused: empty, past the patches; a line job */
    SiExactRows *r0 = NULL, *r1 = NULL, *r = NULL;
    CHECK(si_exact_rows(scene, tol, 3, 3, NULL, &r) == SI_ERR_INVALID_ARGUMENT && r == NULL);
    CHECK(si_exact_rows(scene, tol, 0, n + 1, NULL, &r) == SI_ERR_INVALID_ARGUMENT &&
          r == NULL && says(argv[1]) && says("has rows 0.."));
    SiJob job = {0};
    job.method = SI_METHOD_GLOBAL;
    CHECK(si_exact_rows(scene, tol, 0, n, &job, &r) == SI_ERR_INVALID_ARGUMENT && r == NULL);

    /* The two ranges, on one and on two threads, written and read back */
    job.method = SI_METHOD_EXACT;
    job.threads = 1;
    CHECK(si_exact_rows(scene, tol, 0, split, &job, &r0) == SI_OK);
    job.threads = 2;
    CHECK(si_exact_rows(scene, tol, split, n, &job, &r1) == SI_OK);
    if (r0 == NULL || r1 == NULL) return 1;
    SiExactRowsInfo info;
    CHECK(si_exact_rows_info(r0, &info) == SI_OK);
    CHECK(info.first == 0 && info.end == split && info.n_patches == n && !info.complete &&
          info.tolerance == tol && info.pair_count > 0);
    CHECK(si_exact_rows_write(r0, p0) == SI_OK);
    CHECK(si_exact_rows_write(r1, p1) == SI_OK);
    SiExactRows *f0 = NULL, *f1 = NULL;
    CHECK(si_exact_rows_read(p0, &f0) == SI_OK);
    CHECK(si_exact_rows_read(p1, &f1) == SI_OK);

    /* Bytes: asked for, a short buffer refused, read back as the same rows */
    size_t len = 0;
    CHECK(si_exact_rows_to_bytes(f1, NULL, 0, &len) == SI_ERR_BUFFER_TOO_SMALL && len > 0);
    uint8_t *bytes = malloc(len);
    CHECK(si_exact_rows_to_bytes(f1, bytes, len - 1, NULL) == SI_ERR_BUFFER_TOO_SMALL);
    CHECK(si_exact_rows_to_bytes(f1, bytes, len, &len) == SI_OK);
    SiExactRows *b1 = NULL;
    CHECK(si_exact_rows_from_bytes(bytes, len, &b1) == SI_OK);
    /* A corrupt copy, in memory and as a file; a scene file read as rows */
    bytes[len / 2] ^= 1;
    CHECK(si_exact_rows_from_bytes(bytes, len, &r) == SI_ERR_PARTIAL && r == NULL &&
          says("bytes: bad partial-result file: checksum mismatch"));
    FILE *f = fopen(bad, "wb");
    CHECK(f != NULL && fwrite(bytes, 1, len, f) == len && fclose(f) == 0);
    CHECK(si_exact_rows_read(bad, &r) == SI_ERR_PARTIAL && r == NULL && says(bad));
    CHECK(si_exact_rows_read(argv[1], &r) == SI_ERR_PARTIAL && r == NULL &&
          says("wrong magic bytes"));
    CHECK(si_exact_rows_read(argv[4], &r) == SI_ERR_IO && r == NULL);
    free(bytes);

    /* Merges refused: no parts, a NULL part, overlapping rows, another tolerance; rows
     * missing at measurement */
    const SiExactRows *overlap[] = {f0, r0};
    CHECK(si_exact_rows_merge(overlap, 0, &r) == SI_ERR_INVALID_ARGUMENT && r == NULL);
    const SiExactRows *with_null[] = {f0, NULL};
    CHECK(si_exact_rows_merge(with_null, 2, &r) == SI_ERR_NULL_ARGUMENT && r == NULL);
    CHECK(si_exact_rows_merge(overlap, 2, &r) == SI_ERR_PARTIAL && r == NULL &&
          says("overlap") && says(p0));
    SiExactRows *other = NULL;
    CHECK(si_exact_rows(scene, tol * 2, split, n, NULL, &other) == SI_OK);
    const SiExactRows *mixed[] = {f0, other};
    CHECK(si_exact_rows_merge(mixed, 2, &r) == SI_ERR_PARTIAL && r == NULL &&
          says("tolerance differs"));
    si_exact_rows_free(other);
    SiMeasurement *m = NULL;
    CHECK(si_exact_rows_measurement(f0, &m) == SI_ERR_PARTIAL && m == NULL &&
          says("rows 0..") && says(p0));

    /* The merge, parts in reverse order (one read from bytes), and its measurement */
    const SiExactRows *both[] = {b1, f0};
    SiExactRows *merged = NULL;
    CHECK(si_exact_rows_merge(both, 2, &merged) == SI_OK);
    if (merged == NULL) return 1;
    CHECK(si_exact_rows_info(merged, &info) == SI_OK);
    CHECK(info.first == 0 && info.end == n && info.complete);
    CHECK(si_exact_rows_measurement(merged, &m) == SI_OK);
    if (m == NULL) return 1;

    /* The one job, for comparison: the same bits */
    SiMeasurement *whole = NULL;
    CHECK(si_measure_exact(scene, tol, NULL, &whole) == SI_OK);
    if (whole == NULL) return 1;
    Sparse a = sparse_of(m), w = sparse_of(whole);
    CHECK(a.n == w.n && a.nnz == w.nnz);
    if (a.n == w.n && a.nnz == w.nnz) {
        CHECK(same_bits(a.row_ptr, w.row_ptr, (a.n + 1) * sizeof(size_t)));
        CHECK(same_bits(a.cols, w.cols, a.nnz * sizeof(size_t)));
        CHECK(same_bits(a.vals, w.vals, a.nnz * sizeof(double)));
        CHECK(same_bits(a.errs, w.errs, a.nnz * sizeof(double)));
    }
    CHECK(same_bits(&a.measures, &w.measures, sizeof(SiMeasures)));
    SiExactErrors ea, ew;
    CHECK(si_measurement_exact_errors(m, &ea) == SI_OK);
    CHECK(si_measurement_exact_errors(whole, &ew) == SI_OK);
    CHECK(ea.tolerance == ew.tolerance && ea.max_error == ew.max_error &&
          ea.max_row_error == ew.max_row_error && ea.pairs_integrated == ew.pairs_integrated &&
          ea.pairs_over_tolerance == ew.pairs_over_tolerance && ea.pairs_integrated > 0);
    fprintf(stderr, "    rows 0..%zu + %zu..%zu merged = one job: %zu entries of F and their "
                    "estimates, I_S %.17g, the same bits\n",
            split, split, n, a.nnz, a.measures.i_s);
    for (size_t i = 0; i < a.n; i++) {
        for (size_t k = a.row_ptr[i]; k < a.row_ptr[i + 1]; k++) {
            printf("%zu,%zu,%.17g,%.17g\n", i, a.cols[k], a.vals[k], a.errs[k]);
        }
    }
    sparse_free(&a);
    sparse_free(&w);
    si_measurement_free(m);
    si_measurement_free(whole);
    si_exact_rows_free(merged);
    si_exact_rows_free(b1);
    si_exact_rows_free(f0);
    si_exact_rows_free(f1);
    si_exact_rows_free(r0);
    si_exact_rows_free(r1);

    /* A flatland scene has no exact rows: a job failure */
    const double seg[] = {0, 0, 1, 0, 1, 0, 1, 1, 1, 1, 0, 1, 0, 1, 0, 0};
    SiScene *flat = NULL;
    CHECK(si_scene_from_segments(seg, 4, NULL, 0, &flat) == SI_OK);
    CHECK(si_exact_rows(flat, tol, 0, 4, NULL, &r) == SI_ERR_JOB && r == NULL);
    si_scene_free(flat);
    si_scene_free(scene);
    if (failures > 0) {
        fprintf(stderr, "rows.c: %d checks failed\n", failures);
        return 1;
    }
    return 0;
}
