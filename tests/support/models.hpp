// Where the tests find their meshes. The suite passes from the repository alone:
//   - the CC0 meshes fandisk, elephant and man are in the repository (data/sample/fandisk.stl,
//     tests/data/models/), found by repo_model();
//   - the others (cat and skull, whose licences ask for attribution we do not ship; the synthetic
//     shapes; the broken inputs of bad/) stay in the developers' shared folder,
//     ../shared/models next to the checkout, or wherever CARVE_SHARED_MODELS points. A test that
//     needs one calls CARVE_SHARED_MODEL(var, "cat.stl"): without the file the test is SKIPPED
//     and the skip names the model.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace carve::test {

// The shared models folder: $CARVE_SHARED_MODELS when set (an empty value or a missing folder
// means "not here"), else the one next to the source tree at build time.
inline std::filesystem::path shared_models_dir() {
    if (const char* env = std::getenv("CARVE_SHARED_MODELS")) return env;
    return CARVE_MODELS_DIR;
}

// A mesh of the repository by file name ("fandisk.stl", "elephant.stl", "man.stl").
inline std::string repo_model(const std::string& name) {
    const std::filesystem::path root(CARVE_SOURCE_DIR);
    if (name == "fandisk.stl") return (root / "data" / "sample" / name).string();
    return (root / "tests" / "data" / "models" / name).string();
}

// The path of a shared model ("cat.stl", "bad/empty.stl", "synthetic/torus.stl"), empty when
// the shared folder does not hold it.
inline std::string shared_model(const std::string& name) {
    const std::filesystem::path p = shared_models_dir() / name;
    std::error_code ec;
    return std::filesystem::is_regular_file(p, ec) ? p.string() : std::string();
}

// Any model by name: the repository's when it has it, else the shared folder's (empty if none).
inline std::string any_model(const std::string& name) {
    const std::string own = repo_model(name);
    std::error_code ec;
    if (std::filesystem::is_regular_file(own, ec)) return own;
    return shared_model(name);
}

}  // namespace carve::test

// Declares `std::string var` = the path of model `name` (repository first, then the shared
// folder), or skips the current test, naming the model, when neither holds it.
#define CARVE_MODEL(var, name)                                                \
    const std::string var = ::carve::test::any_model(name);                   \
    if (var.empty())                                                          \
    GTEST_SKIP() << "model " << (name) << " not found (shared models folder " \
                 << ::carve::test::shared_models_dir().string() << ", set CARVE_SHARED_MODELS)"

// Skips the current test, naming the model, when neither the repository nor the shared folder
// holds model `name`.
#define CARVE_NEED_MODEL(name)                                                \
    if (::carve::test::any_model(name).empty())                               \
    GTEST_SKIP() << "model " << (name) << " not found (shared models folder " \
                 << ::carve::test::shared_models_dir().string() << ", set CARVE_SHARED_MODELS)"
