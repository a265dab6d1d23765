/*
 * exact.c: exact 3D form factors with occlusion through the C API, run by
 * `scripts/capi.sh check` under AddressSanitizer.
 *
 *   exact SCENE.vs3 TOLERANCE
 *
 * SCENE.vs3 must be a 3D scene in which some patch hides part of another, read from View3D's
 * input format (tests/data/vs3/room_with_plate.vs3). Checks the tolerance, the error
 * estimates and the sparse form factors with an estimate per entry, a progress callback
 * that stops the job, then prints every entry as `i,j,F_ij,error` (the CLI's `.ijv`
 * order; the entries 0 +- error of si_measurement_zero_form_factor_errors merged in) for
 * capi.sh to compare with `sceneinfo formfactors SCENE --tol TOLERANCE --out F.ijv`, bit
 * for bit. Then a pair hidden behind a plate, decided as 0 +- U: its estimate is read.
 */
#include <sceneinfo.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

static int failures = 0;

#define CHECK(cond)                                                                  \
    do {                                                                             \
        if (!(cond)) {                                                               \
            fprintf(stderr, "exact.c:%d: check failed: %s (last error: %s)\n",       \
                    __LINE__, #cond, si_error_message());                            \
            failures++;                                                              \
        }                                                                            \
    } while (0)

/* Stops the job at its second report (rows done, rows). */
static int stop_early(uint64_t done, uint64_t total, void *user) {
    int *calls = (int *)user;
    (*calls)++;
    return done >= 1 && done < total;
}

int main(int argc, char **argv) {
    if (argc != 3) {
        fprintf(stderr, "usage: exact SCENE.vs3 TOLERANCE\n");
        return 2;
    }
    const double tol = strtod(argv[2], NULL);
    SiScene *scene = NULL;
    SiMeasurement *m = NULL;
    CHECK(si_scene_from_file(argv[1], SI_FORMAT_AUTO, &scene) == SI_OK);
    if (scene == NULL) return 1;

    /* A tolerance out of range, a line job: refused, nothing returned */
    SiJob job = {0};
    CHECK(si_measure_exact(scene, 0.0, &job, &m) == SI_ERR_INVALID_ARGUMENT && m == NULL);
    job.method = SI_METHOD_GLOBAL;
    CHECK(si_measure_exact(scene, tol, &job, &m) == SI_ERR_INVALID_ARGUMENT && m == NULL);
    /* Stopped by the progress callback: SI_STOPPED, nothing returned */
    int calls = 0;
    job.method = SI_METHOD_EXACT;
    job.threads = 1;
    job.progress = stop_early;
    job.user = &calls;
    CHECK(si_measure_exact(scene, tol, &job, &m) == SI_STOPPED && m == NULL && calls >= 1);

    /* The job on two threads */
    job.progress = NULL;
    job.threads = 2;
    CHECK(si_measure_exact(scene, tol, &job, &m) == SI_OK);
    if (m == NULL) return 1;
    SiExactErrors e;
    CHECK(si_measurement_exact_errors(m, &e) == SI_OK);
    CHECK(e.tolerance == tol && e.pairs_integrated > 0 && e.pairs_over_tolerance == 0);
    CHECK(e.max_error > 0 && e.max_error <= tol && e.max_row_error >= e.max_error);

    /* The sparse form factors and their estimates, entry for entry */
    size_t n = si_measurement_n_states(m), np = si_measurement_n_patches(m), nnz = 0, nnz2 = 0;
    CHECK(si_measurement_form_factors_csr(m, NULL, 0, NULL, NULL, 0, &nnz) ==
          SI_ERR_BUFFER_TOO_SMALL);
    CHECK(si_measurement_form_factor_errors_csr(m, NULL, 0, &nnz2) == SI_ERR_BUFFER_TOO_SMALL);
    CHECK(nnz > 0 && nnz2 == nnz);
    size_t *row_ptr = malloc((n + 1) * sizeof(size_t));
    size_t *cols = malloc(nnz * sizeof(size_t));
    double *vals = malloc(nnz * sizeof(double));
    double *errs = malloc(nnz * sizeof(double));
    CHECK(si_measurement_form_factors_csr(m, row_ptr, n + 1, cols, vals, nnz, &nnz) == SI_OK);
    CHECK(si_measurement_form_factor_errors_csr(m, errs, nnz, &nnz2) == SI_OK);
    /* The entries 0 +- error, not among the stored ones, in row order */
    size_t nz = 0, z = 0;
    CHECK(si_measurement_zero_form_factor_errors(m, NULL, NULL, NULL, 0, &nz) ==
          (nz > 0 ? SI_ERR_BUFFER_TOO_SMALL : SI_OK));
    size_t *zr = malloc((nz + 1) * sizeof(size_t)), *zc = malloc((nz + 1) * sizeof(size_t));
    double *ze = malloc((nz + 1) * sizeof(double));
    CHECK(si_measurement_zero_form_factor_errors(m, zr, zc, ze, nz, &nz) == SI_OK);
    for (size_t i = 0; i < n; i++) {
        for (size_t k = row_ptr[i]; k <= row_ptr[i + 1]; k++) {
            /* Zero entries before this stored entry (or, at the row's end, the rest) */
            while (z < nz && zr[z] == i && (k == row_ptr[i + 1] || zc[z] < cols[k])) {
                CHECK(ze[z] > 0 && ze[z] <= tol);
                printf("%zu,%zu,0.0,%.17g\n", zr[z], zc[z], ze[z]);
                z++;
            }
            if (k == row_ptr[i + 1]) break;
            if (i < np && cols[k] < np) {
                CHECK(errs[k] >= 0 && errs[k] <= tol);
            } else {
                CHECK(isnan(errs[k])); /* the background state's entries */
            }
            printf("%zu,%zu,%.17g,%.17g\n", i, cols[k], vals[k], errs[k]);
        }
    }
    CHECK(z == nz);
    free(zr);
    free(zc);
    free(ze);
    free(row_ptr);
    free(cols);
    free(vals);
    free(errs);
    si_measurement_free(m);
    m = NULL;

    /* Squares of side 0.01 at z = 0 (up) and z = 1 (down), a plate of side 1 at z = 0.5
     * between them: the hidden pair's unoccluded flux fits the tolerance 1e-3, so it is
     * decided as 0 +- U (U about A / (pi d^2) = 3.2e-5), not a stored entry */
    const double hv[] = {0, 0, 0, 0.01, 0, 0, 0.01, 0.01, 0, 0, 0.01, 0,
                         0, 0, 1, 0.01, 0, 1, 0.01, 0.01, 1, 0, 0.01, 1,
                         -0.5, -0.5, 0.5, 0.5, -0.5, 0.5, 0.5, 0.5, 0.5, -0.5, 0.5, 0.5};
    const uint32_t hq[] = {0, 1, 2, 3, 4, 7, 6, 5, 8, 11, 10, 9};
    const uint32_t ho[] = {0, 4, 8, 12};
    SiScene *hidden = NULL;
    CHECK(si_scene_from_arrays(hv, 12, hq, 12, ho, 4, NULL, 0, &hidden) == SI_OK);
    CHECK(si_measure_exact(hidden, 1e-3, NULL, &m) == SI_OK);
    size_t hr[2] = {9, 9}, hc[2] = {9, 9}, count = 0;
    double he[2] = {0, 0};
    CHECK(si_measurement_zero_form_factor_errors(m, hr, hc, he, 1, &count) ==
          SI_ERR_BUFFER_TOO_SMALL);
    CHECK(count == 2 && hr[0] == 9);
    CHECK(si_measurement_zero_form_factor_errors(m, hr, hc, he, 2, &count) == SI_OK);
    CHECK(hr[0] == 0 && hc[0] == 1 && hr[1] == 1 && hc[1] == 0);
    CHECK(he[0] > 1e-5 && he[0] <= 1e-3 && he[1] > 1e-5 && he[1] <= 1e-3);
    si_measurement_free(m);
    m = NULL;
    si_scene_free(hidden);

    /* An unoccluded tetrahedron: every form factor exact, no estimates to report */
    const double v[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    const uint32_t tri[] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    SiScene *tet = NULL;
    CHECK(si_scene_from_arrays(v, 4, tri, 12, NULL, 0, NULL, 0, &tet) == SI_OK);
    CHECK(si_measure_exact(tet, tol, NULL, &m) == SI_OK);
    CHECK(si_measurement_exact_errors(m, &e) == SI_ERR_UNDEFINED);
    si_measurement_free(m);
    si_scene_free(tet);
    si_scene_free(scene);
    if (failures > 0) {
        fprintf(stderr, "exact.c: %d checks failed\n", failures);
        return 1;
    }
    return 0;
}
