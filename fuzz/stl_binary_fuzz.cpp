// libFuzzer target: the binary STL reader. The triangle count in the header is set from the
// input's length (load_mesh only hands the reader files whose size matches the count), so that
// every input reaches the facet loop.
#include <cstring>
#include <string>

#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 84) return 0;
    const uint32_t count = static_cast<uint32_t>((size - 84) / 50);
    std::string file(reinterpret_cast<const char*>(data), 84 + 50 * size_t(count));
    const uint8_t le[4] = {uint8_t(count), uint8_t(count >> 8), uint8_t(count >> 16),
                           uint8_t(count >> 24)};
    std::memcpy(file.data() + 80, le, 4);
    return carve::fuzz::run_reader(
        reinterpret_cast<const uint8_t*>(file.data()), file.size(),
        [](std::string_view d, const std::string& path, carve::Mesh& mesh,
           carve::MeshReport& report) { carve::detail::read_binary_stl(d, path, mesh, report); });
}
