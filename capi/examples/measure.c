/*
 * measure.c: measure a scene file through sceneinfo's C API and print the result as JSON,
 * every number with %.17g (enough digits to give back the same double).
 *
 *   measure SCENE [LINES [SEED [THREADS [METHOD]]]]
 *
 * LINES 0 or absent: exact form factors; else LINES lines of METHOD (global, local or
 * bundle; default global) with SEED (default 1) on THREADS threads (default 0: one per
 * core). The keys are those of `sceneinfo measure --json` (scripts/capi.sh compares the
 * two, number for number), plus the per-patch arrays and, for small scenes, the matrix F.
 *
 * Build: cc measure.c $(pkg-config --cflags --libs sceneinfo) -o measure
 */
#include <sceneinfo.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Prints why the last call failed and returns the exit status 2. */
static int fail(const char *what, SiStatus status) {
    fprintf(stderr, "measure: %s failed: %s: %s\n", what, si_status_name(status),
            si_error_message());
    return 2;
}

static void print_number(const char *key, double v) {
    /* JSON has no NaN: an undefined value is null, as in the CLI's report */
    if (isnan(v)) {
        printf(",\n  \"%s\": null", key);
    } else {
        printf(",\n  \"%s\": %.17g", key, v);
    }
}

static void print_values(const double *v, size_t n) {
    printf("[");
    for (size_t k = 0; k < n; k++) {
        printf(k ? ", %.17g" : "%.17g", v[k]);
    }
    printf("]");
}

/* One of the per-patch getters: ask for the length (out = NULL, out_len = 0), allocate,
 * copy, print. Returns SI_OK, or the getter's failure. */
typedef SiStatus (*ArrayGetter)(const SiMeasurement *, double *, size_t, size_t *);

static SiStatus print_array(const char *key, ArrayGetter get, const SiMeasurement *m) {
    size_t needed = 0;
    SiStatus s = get(m, NULL, 0, &needed);
    if (s != SI_OK && s != SI_ERR_BUFFER_TOO_SMALL) {
        return s;
    }
    double *values = malloc((needed ? needed : 1) * sizeof *values);
    if (!values) {
        fprintf(stderr, "measure: out of memory\n");
        exit(2);
    }
    s = get(m, values, needed, &needed);
    if (s == SI_OK) {
        printf(",\n  \"%s\": ", key);
        print_values(values, needed);
    }
    free(values);
    return s;
}

/* The form factors, row by row, for scenes of at most 64 states. */
static SiStatus print_form_factors(const SiMeasurement *m) {
    size_t n = si_measurement_n_states(m);
    if (n == 0 || n > 64) {
        return SI_OK;
    }
    double row[64];
    printf(",\n  \"form_factor_matrix\": [");
    for (size_t i = 0; i < n; i++) {
        size_t needed = 0;
        SiStatus s = si_measurement_form_factor_row(m, i, row, 64, &needed);
        if (s != SI_OK) {
            return s;
        }
        printf(i ? ",\n    " : "\n    ");
        print_values(row, needed);
    }
    printf("]");
    return SI_OK;
}

static int method_of(const char *name, uint32_t *method) {
    static const char *const names[] = {"exact", "global", "local", "bundle"};
    for (uint32_t k = 0; k < 4; k++) {
        if (strcmp(name, names[k]) == 0) {
            *method = k;
            return 1;
        }
    }
    return 0;
}

int main(int argc, char **argv) {
    if (argc < 2 || argc > 6) {
        fprintf(stderr, "usage: %s SCENE [LINES [SEED [THREADS [METHOD]]]]\n", argv[0]);
        return 2;
    }
    SiJob job = {0}; /* zero: the exact job */
    job.seed = 1;
    if (argc > 2) {
        job.lines = strtoull(argv[2], NULL, 10);
        job.method = job.lines ? SI_METHOD_GLOBAL : SI_METHOD_EXACT;
    }
    if (argc > 3) job.seed = strtoull(argv[3], NULL, 10);
    if (argc > 4) job.threads = (uint32_t)strtoul(argv[4], NULL, 10);
    if (argc > 5 && !method_of(argv[5], &job.method)) {
        fprintf(stderr, "measure: unknown method '%s'\n", argv[5]);
        return 2;
    }

    /* The scene: owned by us until si_scene_free */
    SiScene *scene = NULL;
    SiStatus s = si_scene_from_file(argv[1], SI_FORMAT_AUTO, &scene);
    if (s != SI_OK) {
        return fail("si_scene_from_file", s);
    }
    for (size_t k = 0; k < si_scene_warning_count(scene); k++) {
        fprintf(stderr, "measure: warning: %s: %s\n", argv[1], si_scene_warning(scene, k));
    }
    SiLoadReport load;
    s = si_scene_load_report(scene, &load);
    if (s != SI_OK) {
        si_scene_free(scene);
        return fail("si_scene_load_report", s);
    }

    /* The measurement owns its data: the scene can go now */
    SiMeasurement *m = NULL;
    s = si_measure(scene, &job, &m);
    si_scene_free(scene);
    if (s != SI_OK) {
        return fail("si_measure", s);
    }

    int status = 0;
    SiMeasures ms;
    SiLineRun run;
    printf("{\n  \"n_patches\": %zu", si_measurement_n_patches(m));
    s = si_measurement_measures(m, &ms);
    if (s == SI_OK) {
        print_number("h_p", ms.h_p);
        print_number("h_s", ms.h_s);
        print_number("h_j", ms.h_j);
        print_number("i_s", ms.i_s);
        print_number("h_s_norm", ms.h_s_norm);
        print_number("i_s_norm", ms.i_s_norm);
        print_number("e_mse", ms.e_mse);
        print_number("fano", ms.fano);
        print_number("h_s_joint_norm", ms.h_s_joint_norm);
        print_number("i_s_joint_norm", ms.i_s_joint_norm);
        printf(",\n  \"n_states\": %zu", ms.n_states);
        printf(",\n  \"background\": %s", ms.background ? "true" : "false");
        print_number("max_row_deficit", ms.max_row_deficit);
        printf(",\n  \"checks\": {\"min_row_sum\": %.17g, \"max_row_sum\": %.17g, "
               "\"max_row_sum_error\": %.17g, \"max_reciprocity_error\": %.17g, "
               "\"stationarity_error\": %.17g}",
               ms.min_row_sum, ms.max_row_sum, ms.max_row_sum_error, ms.max_reciprocity_error,
               ms.stationarity_error);
    } else if (s != SI_ERR_UNDEFINED) {
        status = fail("si_measurement_measures", s);
    }
    if (si_measurement_line_run(m, &run) == SI_OK) {
        print_number("i_s_continuous", run.i_s_continuous);
        print_number("i_s_continuous_stderr", run.i_s_continuous_stderr);
        print_number("rel_discretisation_error", run.rel_discretisation_error);
        printf(",\n  \"lines\": %llu", (unsigned long long)run.lines);
        printf(",\n  \"seed\": %llu", (unsigned long long)run.seed);
        printf(",\n  \"samples\": %llu", (unsigned long long)run.samples);
        printf(",\n  \"stderr_groups\": %llu", (unsigned long long)run.stderr_groups);
        if (run.unsampled_patches) {
            printf(",\n  \"unsampled_patches\": %zu", run.unsampled_patches);
        }
        s = print_array("patch_continuous", si_measurement_patch_continuous, m);
        if (s != SI_OK) status = fail("si_measurement_patch_continuous", s);
    }
    s = print_array("patch_sizes", si_measurement_patch_sizes, m);
    if (s != SI_OK) status = fail("si_measurement_patch_sizes", s);
    /* Undefined (not a failure) when some patch received no line */
    s = print_array("patch_information", si_measurement_patch_information, m);
    if (s != SI_OK && s != SI_ERR_UNDEFINED) status = fail("si_measurement_patch_information", s);
    s = print_array("patch_entropies", si_measurement_patch_entropies, m);
    if (s != SI_OK && s != SI_ERR_UNDEFINED) status = fail("si_measurement_patch_entropies", s);
    s = print_form_factors(m);
    if (s != SI_OK && s != SI_ERR_UNDEFINED) status = fail("si_measurement_form_factor_row", s);
    if (load.faces_read) {
        /* What the OBJ loader read and repaired (the CLI writes the non-zero counts) */
        printf(",\n  \"faces_read\": %llu", (unsigned long long)load.faces_read);
        printf(",\n  \"repeated_vertices\": %llu", (unsigned long long)load.repeated_vertices);
        printf(",\n  \"faces_flattened\": %llu", (unsigned long long)load.faces_flattened);
        printf(",\n  \"faces_triangulated\": %llu", (unsigned long long)load.faces_triangulated);
        printf(",\n  \"triangles_added\": %llu", (unsigned long long)load.triangles_added);
        printf(",\n  \"pieces_dropped\": %llu", (unsigned long long)load.pieces_dropped);
        printf(",\n  \"duplicates_dropped\": %llu", (unsigned long long)load.duplicates_dropped);
        printf(",\n  \"covered_dropped\": %llu", (unsigned long long)load.covered_dropped);
        printf(",\n  \"overlaps_clipped\": %llu", (unsigned long long)load.overlaps_clipped);
        printf(",\n  \"clip_pieces\": %llu", (unsigned long long)load.clip_pieces);
        print_number("max_off_plane", load.max_off_plane);
    }
    size_t n_warnings = si_measurement_warning_count(m);
    if (n_warnings) {
        printf(",\n  \"warnings\": [");
        for (size_t k = 0; k < n_warnings; k++) {
            /* Warnings are our own text, without quotes or backslashes */
            printf(k ? ", \"%s\"" : "\"%s\"", si_measurement_warning(m, k));
        }
        printf("]");
    }
    printf("\n}\n");
    si_measurement_free(m);
    return status;
}
