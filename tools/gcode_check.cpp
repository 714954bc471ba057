// Stand-alone driver of the G-code analyser for the baseline script (bench/baselines.sh), usable
// before `carve check` exists. It needs only src/report/gcode_analysis.cpp, the stick-time
// trapezoid of src/gcode/motion.cpp and Clipper:
//   g++ -O2 -std=c++20 -Isrc tools/gcode_check.cpp src/report/gcode_analysis.cpp
//       src/gcode/motion.cpp -lpolyclipping   (one line)
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <string>

#include "base/error.hpp"
#include "check/gcode_analysis.hpp"

int main(int argc, char** argv) {
    carve::GcodeAnalysisOptions options;
    std::string file;
    bool json = false, layers = false;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        auto value = [&](const char* name) {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "gcode_check: %s needs a value\n", name);
                std::exit(1);
            }
            return std::atof(argv[++i]);
        };
        if (a == "--json") {
            json = true;
        } else if (a == "--layers") {
            layers = true;
        } else if (a == "--filament-diameter") {
            options.filament_diameter_mm = value("--filament-diameter");
            options.filament_diameter_from_header = false;
        } else if (a == "--bead") {
            std::string b = i + 1 < argc ? argv[++i] : "";
            if (b != "rounded" && b != "rectangle") {
                std::fputs("gcode_check: --bead takes rounded or rectangle\n", stderr);
                return 1;
            }
            options.bead =
                b == "rounded" ? carve::BeadModel::kRounded : carve::BeadModel::kRectangle;
        } else if (a == "--support-radius") {
            options.support_radius_mm = value("--support-radius");
        } else if (a == "--far-radius") {
            options.far_radius_mm = value("--far-radius");
        } else if (a == "-h" || a == "--help") {
            std::puts(
                "usage: gcode_check FILE.gcode [--json] [--layers] [--filament-diameter MM]\n"
                "                   [--support-radius MM] [--far-radius MM] [--bead "
                "rounded|rectangle]");
            return 0;
        } else if (file.empty() && (a.empty() || a[0] != '-')) {
            file = a;
        } else {
            std::fprintf(stderr, "gcode_check: unknown argument '%s'\n", a.c_str());
            return 1;
        }
    }
    if (file.empty()) {
        std::fputs("gcode_check: no G-code file given (see --help)\n", stderr);
        return 1;
    }
    try {
        options.keep_layers = layers;
        carve::GcodeAnalysis a = carve::analyse_gcode(file, options);
        if (json) {
            std::cout << carve::to_json(a, layers).dump(2) << "\n";
        } else {
            std::printf("generator            %s\n", a.generator.c_str());
            std::printf("layers               %d (z %.3f .. %.3f mm)\n", a.layers, a.first_z_mm,
                        a.last_z_mm);
            std::printf("filament             %.1f mm (diameter %.2f mm from %s)\n",
                        a.filament_length_mm, a.filament_diameter_mm,
                        a.filament_diameter_source.c_str());
            std::printf("extruded volume      %.1f mm3\n", a.extruded_volume_mm3);
            std::printf("mean line width      %.3f mm (%s bead)\n", a.mean_line_width_mm,
                        a.bead_model.c_str());
            std::printf("footprint            %.1f mm2 (sum over layers)\n", a.footprint_area_mm2);
            std::printf("unsupported (r=%.2f) %.2f mm2 = %.3f %%\n", options.support_radius_mm,
                        a.unsupported_area_mm2, 100 * a.unsupported_fraction);
            std::printf("far-unsupported      %.2f mm2 = %.3f %%\n", a.far_unsupported_area_mm2,
                        100 * a.far_unsupported_fraction);
            if (a.estimated_time_from_header_s >= 0)
                std::printf("header time          %.0f s\n", a.estimated_time_from_header_s);
        }
    } catch (const carve::InputError& e) {
        std::fprintf(stderr, "gcode_check: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "gcode_check: internal error: %s\n", e.what());
        return 2;
    }
    return 0;
}
