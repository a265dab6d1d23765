/*
 * errors.c: the C API's failure paths, run by `scripts/capi.sh check` under
 * AddressSanitizer: every failure is a status and a message, never a crash or a leak.
 *
 *   errors BAD.flat OCCLUDED.obj LIT.flat
 *
 * BAD.flat must fail to parse on line 1 (tests/data/bad/not_a_number.flat); OCCLUDED.obj
 * must be a 3D scene whose exact form factors are refused (the Cornell box); LIT.flat a
 * flatland scene with a lamp (capi/tests/lit.flat).
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
            fprintf(stderr, "errors.c:%d: check failed: %s (last error: %s)\n",      \
                    __LINE__, #cond, si_error_message());                            \
            failures++;                                                              \
        }                                                                            \
    } while (0)

/* A progress callback's record: calls, the last (done, total), and after how many calls
 * it asks to stop (0: never). */
typedef struct {
    int calls, stop_after, rising;
    uint64_t done, total;
} Watch;

static int watch(uint64_t done, uint64_t total, void *user) {
    Watch *w = (Watch *)user;
    if (done <= w->done || done > total) w->rising = 0;
    w->calls++;
    w->done = done;
    w->total = total;
    return w->stop_after > 0 && w->calls >= w->stop_after;
}

/* The last message contains `part`. */
static int says(const char *part) {
    return strstr(si_error_message(), part) != NULL;
}

int main(int argc, char **argv) {
    if (argc != 4) {
        fprintf(stderr, "usage: %s BAD.flat OCCLUDED.obj LIT.flat\n", argv[0]);
        return 2;
    }
    SiScene *scene = (SiScene *)1; /* must be overwritten with NULL on failure */
    SiMeasurement *m = NULL;

    /* A bad file: SI_ERR_SCENE, file:line: what, the line, and *out = NULL */
    CHECK(si_scene_from_file(argv[1], SI_FORMAT_AUTO, &scene) == SI_ERR_SCENE);
    CHECK(scene == NULL);
    CHECK(si_error_code() == SI_ERR_SCENE);
    CHECK(si_error_line() == 1);
    CHECK(says(argv[1]) && says(":1: ") && says("not a number"));
    printf("bad file: %s\n", si_error_message());

    /* A missing file, a folder, an unknown format code */
    CHECK(si_scene_from_file("/nonexistent/scene.flat", SI_FORMAT_AUTO, &scene) == SI_ERR_IO);
    CHECK(says("/nonexistent/scene.flat: cannot read"));
    CHECK(si_scene_from_file("/", SI_FORMAT_FLAT, &scene) == SI_ERR_IO);
    CHECK(says("not a regular file"));
    /* Any extension is read by content, as the CLI reads it: a missing one is SI_ERR_IO */
    CHECK(si_scene_from_file("scene.txt", SI_FORMAT_AUTO, &scene) == SI_ERR_IO);
    CHECK(si_scene_from_file(argv[1], 99, &scene) == SI_ERR_INVALID_ARGUMENT);

    /* NULL arguments */
    CHECK(si_scene_from_file(NULL, SI_FORMAT_AUTO, &scene) == SI_ERR_NULL_ARGUMENT);
    CHECK(si_scene_from_file(argv[2], SI_FORMAT_AUTO, NULL) == SI_ERR_NULL_ARGUMENT);
    CHECK(si_measure(NULL, NULL, &m) == SI_ERR_NULL_ARGUMENT && m == NULL);
    CHECK(si_scene_n_patches(NULL) == 0 && si_measurement_n_states(NULL) == 0);
    si_scene_free(NULL);
    si_measurement_free(NULL);

    /* An occluded 3D scene: exact form factors refused (SI_ERR_JOB), lines work */
    CHECK(si_scene_from_file(argv[2], SI_FORMAT_AUTO, &scene) == SI_OK);
    CHECK(si_error_code() == SI_OK && strcmp(si_error_message(), "") == 0);
    SiJob job = {0};
    CHECK(si_measure(scene, &job, &m) == SI_ERR_JOB && m == NULL);
    CHECK(says(argv[2]));
    printf("occluded exact: %s\n", si_error_message());
    job.method = 7;
    CHECK(si_measure(scene, &job, &m) == SI_ERR_INVALID_ARGUMENT);
    job.method = SI_METHOD_GLOBAL;
    job.lines = (uint64_t)1 << 60; /* above the cap of 2^53 */
    CHECK(si_measure(scene, &job, &m) == SI_ERR_JOB);
    job.lines = 1000;
    job.max_memory = 1000; /* bytes: far too few */
    CHECK(si_measure(scene, &job, &m) == SI_ERR_JOB && says("allowed"));

    /* Too few lines to reach every patch: the measures are undefined, I_S^c is not */
    job.max_memory = 0;
    job.lines = 3;
    CHECK(si_measure(scene, &job, &m) == SI_OK);
    SiMeasures ms;
    SiLineRun run;
    CHECK(si_measurement_measures(m, &ms) == SI_ERR_UNDEFINED);
    CHECK(si_measurement_line_run(m, &run) == SI_OK && run.unsampled_patches > 0);
    CHECK(isnan(run.rel_discretisation_error) || run.i_s_continuous <= 0);
    size_t needed = 0;
    CHECK(si_measurement_patch_information(m, NULL, 0, &needed) == SI_ERR_UNDEFINED);
    CHECK(si_measurement_warning_count(m) >= 1 && si_measurement_warning(m, 99) == NULL);
    si_measurement_free(m);
    m = NULL;
    si_scene_free(scene);

    /* Arrays: a tetrahedron seen from inside (faces counter-clockwise from within) */
    const double v[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    const uint32_t tri[] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    const uint32_t bad[] = {0, 1, 2, 0, 3, 9};
    const uint32_t offsets[] = {0, 3, 6};
    CHECK(si_scene_from_arrays(v, 4, tri, 12, NULL, 0, NULL, 0, &scene) == SI_OK);
    CHECK(si_scene_n_patches(scene) == 4 && !si_scene_is_flat(scene));
    CHECK(si_measure(scene, NULL, &m) == SI_OK);
    /* Buffers: the length asked for, a short buffer refused, then the copy */
    double row[8] = {0};
    CHECK(si_measurement_form_factor_row(m, 0, NULL, 0, &needed) == SI_ERR_BUFFER_TOO_SMALL);
    CHECK(needed == si_measurement_n_states(m) && needed >= 4);
    CHECK(si_measurement_form_factor_row(m, 0, row, needed - 1, &needed) == SI_ERR_BUFFER_TOO_SMALL);
    CHECK(row[0] == 0 && row[1] == 0); /* nothing written */
    CHECK(si_measurement_form_factor_row(m, 0, row, 8, &needed) == SI_OK);
    CHECK(si_measurement_form_factor_row(m, 99, row, 8, &needed) == SI_ERR_INVALID_ARGUMENT);
    double dense[64];
    CHECK(si_measurement_form_factors_dense(m, dense, 64, &needed) == SI_OK);
    CHECK(needed == si_measurement_n_states(m) * si_measurement_n_states(m));
    CHECK(memcmp(dense, row, si_measurement_n_states(m) * sizeof(double)) == 0);
    CHECK(si_measurement_line_run(m, &run) == SI_ERR_UNDEFINED);
    CHECK(si_measurement_patch_continuous(m, row, 8, &needed) == SI_ERR_UNDEFINED);
    CHECK(si_measurement_measures(m, &ms) == SI_OK && ms.n_patches == 4);
    CHECK(ms.i_s > 0 && fabs(ms.h_j - (ms.h_p + ms.h_s)) < 1e-9);
    printf("tetrahedron from arrays: %zu patches, I_S = %.17g\n", ms.n_patches, ms.i_s);
    si_measurement_free(m);
    si_scene_free(scene);
    /* An index past the vertices: the polygon's row */
    CHECK(si_scene_from_arrays(v, 4, bad, 6, offsets, 3, NULL, 0, &scene) == SI_ERR_SCENE);
    CHECK(scene == NULL && si_error_line() == 2 && says("polygon row 2"));
    printf("bad arrays: %s\n", si_error_message());
    CHECK(si_scene_from_arrays(v, 4, tri, 11, NULL, 0, NULL, 0, &scene) == SI_ERR_INVALID_ARGUMENT);
    CHECK(si_scene_from_arrays(NULL, 4, tri, 12, NULL, 0, NULL, 0, &scene) == SI_ERR_NULL_ARGUMENT);
    SiMaterial one = {{0.5, 0.5, 0.5}, {0, 0, 0}};
    CHECK(si_scene_from_arrays(v, 4, tri, 12, NULL, 0, &one, 1, &scene) == SI_ERR_SCENE);

    /* Flatland segments: a square room facing inwards */
    const double square[] = {0, 0, 1, 0, 1, 0, 1, 1, 1, 1, 0, 1, 0, 1, 0, 0};
    CHECK(si_scene_from_segments(square, 4, NULL, 0, &scene) == SI_OK);
    CHECK(si_scene_is_flat(scene) && si_scene_n_patches(scene) == 4);
    double sizes[4];
    CHECK(si_scene_patch_sizes(scene, sizes, 4, &needed) == SI_OK && sizes[0] == 0.25);
    si_scene_free(scene);
    const double zero[] = {0, 0, 0, 0};
    CHECK(si_scene_from_segments(zero, 1, NULL, 0, &scene) == SI_ERR_SCENE && si_error_line() == 1);
    printf("bad segment: %s\n", si_error_message());

    /* Radiosity: refusals, the lit scene's channels, its visibility as a measurement */
    SiLighting *lit = (SiLighting *)1;
    SiRadiosityJob rjob = {0};
    CHECK(si_scene_from_file(argv[2], SI_FORMAT_AUTO, &scene) == SI_OK);
    rjob.form_factors.method = SI_METHOD_GLOBAL;
    rjob.form_factors.lines = 3; /* too few: the solve needs every row of F */
    CHECK(si_radiosity(scene, &rjob, &lit) == SI_ERR_JOB && lit == NULL);
    printf("radiosity on unsampled patches: %s\n", si_error_message());
    si_scene_free(scene);
    CHECK(si_scene_from_file(argv[3], SI_FORMAT_AUTO, &scene) == SI_OK);
    rjob = (SiRadiosityJob){0};
    rjob.solver = 9;
    CHECK(si_radiosity(scene, &rjob, &lit) == SI_ERR_INVALID_ARGUMENT);
    rjob.solver = SI_SOLVER_JACOBI;
    rjob.tolerance = -1;
    CHECK(si_radiosity(scene, &rjob, &lit) == SI_ERR_INVALID_ARGUMENT);
    rjob.tolerance = 1e-300;
    rjob.max_iterations = 1;
    CHECK(si_radiosity(scene, &rjob, &lit) == SI_ERR_JOB);
    printf("no convergence: %s\n", si_error_message());
    CHECK(si_radiosity(scene, NULL, &lit) == SI_OK);
    SiRadiosityMeasures rm;
    CHECK(si_lighting_measures(lit, 3, &rm) == SI_ERR_INVALID_ARGUMENT);
    CHECK(si_lighting_measures(lit, 0, &rm) == SI_OK && rm.light_flows && rm.i_s > 0);
    CHECK(rm.residual <= 1e-10 && fabs(rm.h_j - (rm.h_p + rm.h_s)) < 1e-9);
    SiLitLines lit_lines;
    CHECK(si_lighting_lines(lit, &lit_lines) == SI_ERR_UNDEFINED);
    CHECK(si_lighting_radiosity(lit, 1, NULL, 0, &needed) == SI_ERR_BUFFER_TOO_SMALL);
    CHECK(si_lighting_visibility(lit, &m) == SI_OK);
    CHECK(needed == si_measurement_n_states(m));
    CHECK(si_measurement_measures(m, &ms) == SI_OK && ms.n_patches == si_scene_n_patches(scene));
    printf("lit scene: %zu patches, radiosity I_S (red) = %.17g, visibility I_S = %.17g\n",
           ms.n_patches, rm.i_s, ms.i_s);
    si_measurement_free(m);
    si_lighting_free(lit);
    si_lighting_free(NULL);
    si_scene_free(scene);

    /* Sparse F (CSR) against the dense one: the lit scene, exact */
    CHECK(si_scene_from_file(argv[3], SI_FORMAT_AUTO, &scene) == SI_OK);
    CHECK(si_measure(scene, NULL, &m) == SI_OK);
    {
        size_t n = si_measurement_n_states(m), nnz = 0, dense_nonzero = 0, agree = 1;
        CHECK(si_measurement_form_factors_csr(m, NULL, 0, NULL, NULL, 0, &nnz) ==
              SI_ERR_BUFFER_TOO_SMALL);
        CHECK(nnz > 0 && nnz <= n * n);
        double *dense = malloc(n * n * sizeof(double));
        size_t *row_ptr = malloc((n + 1) * sizeof(size_t));
        size_t *cols = malloc(nnz * sizeof(size_t));
        double *vals = malloc(nnz * sizeof(double));
        CHECK(si_measurement_form_factors_dense(m, dense, n * n, NULL) == SI_OK);
        /* One value short: refused, nothing written */
        row_ptr[0] = 7;
        CHECK(si_measurement_form_factors_csr(m, row_ptr, n + 1, cols, vals, nnz - 1, NULL) ==
              SI_ERR_BUFFER_TOO_SMALL && row_ptr[0] == 7);
        CHECK(si_measurement_form_factors_csr(m, row_ptr, n, cols, vals, nnz, NULL) ==
              SI_ERR_BUFFER_TOO_SMALL);
        CHECK(si_measurement_form_factors_csr(m, row_ptr, n + 1, cols, vals, nnz, NULL) == SI_OK);
        CHECK(row_ptr[0] == 0 && row_ptr[n] == nnz);
        for (size_t i = 0; i < n; i++) {
            size_t k = row_ptr[i];
            for (size_t j = 0; j < n; j++) {
                double f = dense[i * n + j];
                dense_nonzero += f != 0.0;
                if (k < row_ptr[i + 1] && cols[k] == j) {
                    agree &= memcmp(&vals[k], &f, sizeof(double)) == 0;
                    k++;
                } else {
                    agree &= f == 0.0;
                }
            }
            agree &= k == row_ptr[i + 1];
        }
        CHECK(agree && dense_nonzero == nnz);
        printf("sparse F: %zu states, %zu non-zero entries, equal to the dense F bit for bit\n",
               n, nnz);
        free(dense);
        free(row_ptr);
        free(cols);
        free(vals);
    }
    si_measurement_free(m);
    si_scene_free(scene);

    /* Progress and stop: a line job of 20 chunks on 2 threads, the Cornell box */
    CHECK(si_scene_from_file(argv[2], SI_FORMAT_AUTO, &scene) == SI_OK);
    const uint64_t chunk = (uint64_t)1 << 16;
    Watch w = {0, 0, 1, 0, 0};
    SiJob pj = {0};
    pj.size = sizeof(SiJob);
    pj.method = SI_METHOD_GLOBAL;
    pj.threads = 2;
    pj.seed = 5;
    pj.lines = 20 * chunk - 1000; /* the last chunk short */
    pj.progress = watch;
    pj.user = &w;
    CHECK(si_measure(scene, &pj, &m) == SI_OK);
    CHECK(w.calls == 20 && w.rising && w.done == pj.lines && w.total == pj.lines);
    SiLineRun full;
    CHECK(si_measurement_line_run(m, &full) == SI_OK && !full.interrupted);
    CHECK(full.lines == pj.lines && full.budget_done == pj.lines);
    si_measurement_free(m);
    /* Stop after the 3rd chunk: SI_STOPPED, a result of the chunks cast (a prefix) */
    w = (Watch){0, 3, 1, 0, 0};
    m = NULL;
    CHECK(si_measure(scene, &pj, &m) == SI_STOPPED && m != NULL);
    CHECK(si_error_code() == SI_STOPPED && says("stopped"));
    printf("stopped: %s\n", si_error_message());
    SiLineRun part;
    CHECK(si_measurement_line_run(m, &part) == SI_OK && part.interrupted == 1);
    CHECK(part.lines >= 3 * chunk && part.lines < pj.lines && part.lines % chunk == 0);
    CHECK(part.requested == pj.lines && part.budget_done == part.lines);
    /* The same numbers as a job of budget_done lines, bit for bit */
    SiJob again = pj;
    again.lines = part.budget_done;
    again.progress = NULL;
    SiMeasurement *m2 = NULL;
    SiLineRun whole;
    CHECK(si_measure(scene, &again, &m2) == SI_OK);
    CHECK(si_measurement_line_run(m2, &whole) == SI_OK && !whole.interrupted);
    CHECK(memcmp(&whole.i_s_continuous, &part.i_s_continuous, sizeof(double)) == 0);
    CHECK(whole.lines == part.lines && whole.samples == part.samples);
    printf("stopped after %d progress calls: %llu of %llu lines, I_S^c = %.17g (a job of "
           "%llu lines: the same bits)\n", w.calls, (unsigned long long)part.lines,
           (unsigned long long)part.requested, part.i_s_continuous,
           (unsigned long long)part.budget_done);
    si_measurement_free(m2);
    si_measurement_free(m);
    /* A size other than 0 or sizeof(SiJob) */
    pj.size = 8;
    CHECK(si_measure(scene, &pj, &m) == SI_ERR_INVALID_ARGUMENT && m == NULL);
    si_scene_free(scene);
    /* Radiosity stopped: SI_STOPPED and no result */
    CHECK(si_scene_from_file(argv[3], SI_FORMAT_AUTO, &scene) == SI_OK);
    rjob = (SiRadiosityJob){0};
    rjob.form_factors.method = SI_METHOD_GLOBAL;
    rjob.form_factors.lines = 8 * chunk;
    rjob.form_factors.threads = 2;
    rjob.form_factors.progress = watch;
    rjob.form_factors.user = &w;
    w = (Watch){0, 1, 1, 0, 0};
    lit = (SiLighting *)1;
    CHECK(si_radiosity(scene, &rjob, &lit) == SI_STOPPED && lit == NULL);
    printf("radiosity stopped: %s\n", si_error_message());
    si_scene_free(scene);

    printf("%s: %s\n", si_version(), failures ? "FAILED" : "all checks passed");
    return failures ? 1 : 0;
}
