// libFuzzer target: the OBJ reader, fed any text.
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return carve::fuzz::run_reader(
        data, size,
        [](std::string_view d, const std::string& path, carve::Mesh& mesh,
           carve::MeshReport& report) { carve::detail::read_obj(d, path, mesh, report); });
}
