// measure.cpp: I_S of a scene file in ten lines of C++ (exact form factors; a unique_ptr
// frees each handle). Build: c++ measure.cpp $(pkg-config --cflags --libs sceneinfo)
#include <sceneinfo.h>
#include <cstdio>
#include <memory>

int main(int argc, char **argv) {
    SiScene *s = nullptr;
    SiMeasurement *m = nullptr;
    SiMeasures ms{};
    if (argc != 2 || si_scene_from_file(argv[1], SI_FORMAT_AUTO, &s) != SI_OK) return std::fprintf(stderr, "%s\n", si_error_message()), 2;
    std::unique_ptr<SiScene, decltype(&si_scene_free)> scene(s, si_scene_free);
    if (si_measure(scene.get(), nullptr, &m) != SI_OK) return std::fprintf(stderr, "%s\n", si_error_message()), 2;
    std::unique_ptr<SiMeasurement, decltype(&si_measurement_free)> measurement(m, si_measurement_free);
    if (si_measurement_measures(measurement.get(), &ms) != SI_OK) return std::fprintf(stderr, "%s\n", si_error_message()), 2;
    std::printf("%zu patches: I_S = %.17g bits, H_S = %.17g bits\n", ms.n_patches, ms.i_s, ms.h_s);
}
