/*
 * view3d.c: View3D's output surfaces of a .vs3 file through the C API, run by
 * `scripts/capi.sh check` under AddressSanitizer.
 *
 *   view3d WINDOW.vs3
 *
 * WINDOW.vs3 is tests/data/vs3/surface-kinds/window.vs3: a unit cube whose floor holds a
 * 0.5 x 0.5 window (a View3D subsurface). Checks the buffer rules, the seven surfaces
 * View3D reports (the floor keeps 0.75, the window 0.25) and the window's row against
 * View3D 4.0.0's output for the file (window.view3d.txt: six printed decimals, plus the
 * tolerance 1e-6).
 */
#include <sceneinfo.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static int failures = 0;

#define CHECK(cond)                                                                  \
    do {                                                                             \
        if (!(cond)) {                                                               \
            fprintf(stderr, "view3d.c:%d: check failed: %s (last error: %s)\n",      \
                    __LINE__, #cond, si_error_message());                            \
            failures++;                                                              \
        }                                                                            \
    } while (0)

int main(int argc, char **argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: view3d WINDOW.vs3\n");
        return 2;
    }
    SiScene *scene = NULL;
    SiMeasurement *m = NULL;
    CHECK(si_scene_from_file(argv[1], SI_FORMAT_AUTO, &scene) == SI_OK);
    if (scene == NULL) return 1;
    SiJob job = {0};
    job.method = SI_METHOD_EXACT;
    job.threads = 1;
    CHECK(si_measure_exact(scene, 1e-6, &job, &m) == SI_OK);
    if (m == NULL) return 1;
    /* The floor is cut around the window: more patches than View3D's surfaces */
    CHECK(si_measurement_n_patches(m) > 7);

    size_t needed = 0, n = 0;
    CHECK(si_view3d_surfaces(argv[1], m, NULL, 0, &needed, &n) == SI_ERR_BUFFER_TOO_SMALL);
    CHECK(n == 7 && needed == n + n * n);
    double *v = malloc(needed * sizeof(double));
    CHECK(si_view3d_surfaces(argv[1], m, v, needed, &needed, &n) == SI_OK);
    const double areas[7] = {0.75, 1, 1, 1, 1, 1, 0.25};
    /* View3D 4.0.0's row of the window (window.view3d.txt, line 9) */
    const double window_row[7] = {0.0, 0.192885, 0.192885, 0.228461, 0.192885, 0.192885, 0.0};
    for (size_t k = 0; k < 7; k++) {
        CHECK(fabs(v[k] - areas[k]) <= 1e-15);
        CHECK(fabs(v[7 + 6 * 7 + k] - window_row[k]) <= 1.5e-6);
    }
    /* A missing file: SI_ERR_IO */
    CHECK(si_view3d_surfaces("no-such-file.vs3", m, v, needed, NULL, NULL) == SI_ERR_IO);
    free(v);
    si_measurement_free(m);
    si_scene_free(scene);
    if (failures) return 1;
    printf("view3d.c: 7 View3D surfaces of %s, the window's row within 1.5e-6 of View3D's\n",
           argv[1]);
    return 0;
}
