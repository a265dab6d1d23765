/*
 * radiosity.c: light a scene through sceneinfo's C API (B = E + ρFB per colour channel)
 * and print its radiosity measures as JSON, every number with %.17g.
 *
 *   radiosity SCENE [LINES [SEED [THREADS [METHOD [ka]]]]]
 *
 * LINES 0 or absent: exact form factors; else LINES lines of METHOD (global, local or
 * bundle) with SEED on THREADS threads. `ka`: an OBJ's materials without Ke emit their
 * ambient Ka (the CLI's --emit-from-ka). The keys are those of `sceneinfo radiosity
 * --json` (scripts/capi.sh compares the two, number for number).
 *
 * Build: cc radiosity.c $(pkg-config --cflags --libs sceneinfo) -o radiosity
 */
#include <sceneinfo.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const CHANNELS[3] = {"red", "green", "blue"};

static int fail(const char *what, SiStatus status) {
    fprintf(stderr, "radiosity: %s failed: %s: %s\n", what, si_status_name(status),
            si_error_message());
    return 2;
}

static void print_triple(const char *key, const double v[3]) {
    printf(",\n  \"%s\": [%.17g, %.17g, %.17g]", key, v[0], v[1], v[2]);
}

int main(int argc, char **argv) {
    if (argc < 2 || argc > 7) {
        fprintf(stderr, "usage: %s SCENE [LINES [SEED [THREADS [METHOD [ka]]]]]\n", argv[0]);
        return 2;
    }
    SiRadiosityJob job = {0}; /* exact form factors, Gauss-Seidel, default stopping rule */
    job.form_factors.seed = 1;
    if (argc > 2) {
        job.form_factors.lines = strtoull(argv[2], NULL, 10);
        job.form_factors.method = job.form_factors.lines ? SI_METHOD_GLOBAL : SI_METHOD_EXACT;
    }
    if (argc > 3) job.form_factors.seed = strtoull(argv[3], NULL, 10);
    if (argc > 4) job.form_factors.threads = (uint32_t)strtoul(argv[4], NULL, 10);
    if (argc > 5) {
        if (strcmp(argv[5], "local") == 0) job.form_factors.method = SI_METHOD_LOCAL;
        else if (strcmp(argv[5], "bundle") == 0) job.form_factors.method = SI_METHOD_BUNDLE;
    }

    SiLoadOptions load = {0}; /* SI_FORMAT_AUTO: by the extension */
    load.emit_from_ka = argc > 6 && strcmp(argv[6], "ka") == 0;
    SiScene *scene = NULL;
    SiStatus s = si_scene_from_file_with(argv[1], &load, &scene);
    if (s != SI_OK) return fail("si_scene_from_file", s);
    SiLighting *lit = NULL;
    s = si_radiosity(scene, &job, &lit);
    si_scene_free(scene);
    if (s != SI_OK) return fail("si_radiosity", s);

    /* The visibility channel the light was solved on: a measurement of its own */
    SiMeasurement *vis = NULL;
    SiMeasures ms;
    s = si_lighting_visibility(lit, &vis);
    if (s == SI_OK) s = si_measurement_measures(vis, &ms);
    if (s != SI_OK) {
        si_measurement_free(vis);
        si_lighting_free(lit);
        return fail("the visibility measures", s);
    }
    printf("{\n  \"n_patches\": %zu", ms.n_patches);
    printf(",\n  \"h_p\": %.17g,\n  \"h_s\": %.17g,\n  \"h_j\": %.17g,\n  \"i_s\": %.17g",
           ms.h_p, ms.h_s, ms.h_j, ms.i_s);
    printf(",\n  \"h_s_norm\": %.17g,\n  \"i_s_norm\": %.17g", ms.h_s_norm, ms.i_s_norm);
    printf(",\n  \"e_mse\": %.17g,\n  \"fano\": %.17g", ms.e_mse, ms.fano);
    printf(",\n  \"h_s_joint_norm\": %.17g,\n  \"i_s_joint_norm\": %.17g", ms.h_s_joint_norm,
           ms.i_s_joint_norm);
    printf(",\n  \"n_states\": %zu", ms.n_states);
    printf(",\n  \"background\": %s", ms.background ? "true" : "false");
    printf(",\n  \"max_row_deficit\": %.17g", ms.max_row_deficit);
    printf(",\n  \"checks\": {\"min_row_sum\": %.17g, \"max_row_sum\": %.17g, "
           "\"max_row_sum_error\": %.17g, \"max_reciprocity_error\": %.17g, "
           "\"stationarity_error\": %.17g}",
           ms.min_row_sum, ms.max_row_sum, ms.max_row_sum_error, ms.max_reciprocity_error,
           ms.stationarity_error);
    size_t n_warnings = si_measurement_warning_count(vis);
    if (n_warnings) {
        printf(",\n  \"warnings\": [");
        for (size_t k = 0; k < n_warnings; k++) {
            printf(k ? ", \"%s\"" : "\"%s\"", si_measurement_warning(vis, k));
        }
        printf("]");
    }
    si_measurement_free(vis);

    /* Per colour channel: the solve and the radiosity channel's measures */
    SiRadiosityMeasures rm[3];
    for (uint32_t c = 0; c < 3; c++) {
        s = si_lighting_measures(lit, c, &rm[c]);
        if (s != SI_OK) {
            si_lighting_free(lit);
            return fail("si_lighting_measures", s);
        }
    }
    double iterations[3], residual[3], h_p[3], h_s[3], h_j[3], i_s[3];
    for (int c = 0; c < 3; c++) {
        iterations[c] = (double)rm[c].iterations;
        residual[c] = rm[c].residual;
        h_p[c] = rm[c].h_p;
        h_s[c] = rm[c].h_s;
        h_j[c] = rm[c].h_j;
        i_s[c] = rm[c].i_s;
    }
    /* The slowest channel's */
    double most = 0, worst = 0;
    for (int c = 0; c < 3; c++) {
        most = iterations[c] > most ? iterations[c] : most;
        worst = residual[c] > worst ? residual[c] : worst;
    }
    printf(",\n  \"iterations\": %.17g,\n  \"residual\": %.17g", most, worst);
    print_triple("iterations_rgb", iterations);
    print_triple("residual_rgb", residual);
    print_triple("h_p_rgb", h_p);
    print_triple("h_s_rgb", h_s);
    print_triple("h_j_rgb", h_j);
    print_triple("i_s_rgb", i_s);
    printf(",\n  \"light_flows_rgb\": {\"red\": %s, \"green\": %s, \"blue\": %s}",
           rm[0].light_flows ? "true" : "false", rm[1].light_flows ? "true" : "false",
           rm[2].light_flows ? "true" : "false");

    /* B per channel, one per state: ask for the length, then copy */
    size_t n = 0;
    si_lighting_radiosity(lit, 0, NULL, 0, &n);
    double *b = malloc((n ? n : 1) * sizeof *b);
    if (!b) {
        fprintf(stderr, "radiosity: out of memory\n");
        exit(2);
    }
    printf(",\n  \"radiosity\": {");
    for (uint32_t c = 0; c < 3; c++) {
        s = si_lighting_radiosity(lit, c, b, n, &n);
        if (s != SI_OK) {
            free(b);
            si_lighting_free(lit);
            return fail("si_lighting_radiosity", s);
        }
        printf(c ? ", \"%s\": [" : "\"%s\": [", CHANNELS[c]);
        /* The patches' (a background state, if any, is last) */
        for (size_t i = 0; i < ms.n_patches && i < n; i++) printf(i ? ", %.17g" : "%.17g", b[i]);
        printf("]");
    }
    printf("}");
    free(b);

    SiLitLines lines;
    if (si_lighting_lines(lit, &lines) == SI_OK) {
        printf(",\n  \"i_s_continuous\": %.17g", lines.i_s_continuous);
        printf(",\n  \"i_s_continuous_stderr\": %.17g", lines.i_s_continuous_stderr);
        print_triple("i_s_continuous_rgb", lines.radiosity_i_s_continuous);
        print_triple("i_s_continuous_stderr_rgb", lines.radiosity_i_s_continuous_stderr);
        /* The discretisation error of each channel: I_S^c - I_S (5.20 vs 5.7) */
        double delta[3];
        for (int c = 0; c < 3; c++) delta[c] = lines.radiosity_i_s_continuous[c] - rm[c].i_s;
        print_triple("discretisation_error_rgb", delta);
        printf(",\n  \"line_casts\": %d", lines.one_pass ? 1 : 2);
        printf(",\n  \"lines\": %llu", (unsigned long long)lines.lines);
        printf(",\n  \"seed\": %llu", (unsigned long long)lines.seed);
        printf(",\n  \"samples\": %llu", (unsigned long long)lines.samples);
        printf(",\n  \"stderr_groups\": %llu", (unsigned long long)lines.stderr_groups);
    }
    printf("\n}\n");
    si_lighting_free(lit);
    return 0;
}
