// libFuzzer target: the ASCII STL reader, fed any text, whole and through the block reader
// (from a memory stream); both must refuse or both read the same mesh.
#include <cstdio>
#include <cstdlib>

#include "fuzz_common.hpp"

namespace {

// The block reader's answer: the mesh, or nothing when it refused the text.
bool read_streamed(const uint8_t* data, size_t size, carve::Mesh& mesh) {
    std::FILE* f = fmemopen(const_cast<uint8_t*>(data), size, "rb");
    if (!f) return false;
    carve::MeshReport report;
    bool ok = true;
    try {
        carve::detail::read_ascii_stl(f, size, "fuzz", mesh, report, nullptr);
    } catch (const carve::InputError&) {
        ok = false;
    }
    std::fclose(f);
    return ok;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    // fmemopen refuses an empty buffer; the block reader refuses a word over 1 MB that the
    // whole-text reader takes.
    if (size == 0 || size > (1u << 20)) return 0;
    carve::Mesh whole;
    carve::MeshReport report;
    bool whole_ok = true;
    try {
        // The loader strips a BOM before the whole-text reader; the block reader skips it.
        std::string_view text(reinterpret_cast<const char*>(data), size);
        if (text.substr(0, 3) == std::string_view("\xEF\xBB\xBF", 3)) text.remove_prefix(3);
        carve::detail::read_ascii_stl(text, "fuzz", whole, report);
    } catch (const carve::InputError&) {
        whole_ok = false;
    }
    carve::Mesh streamed;
    const bool streamed_ok = read_streamed(data, size, streamed);
    if (whole_ok != streamed_ok ||
        (whole_ok && (whole.triangles != streamed.triangles ||
                      whole.vertices.size() != streamed.vertices.size())))
        std::abort();  // the two readers disagree
    return carve::fuzz::run_reader(
        data, size,
        [](std::string_view d, const std::string& path, carve::Mesh& mesh, carve::MeshReport& r) {
            carve::detail::read_ascii_stl(d, path, mesh, r);
        });
}
