// libFuzzer target: the 3MF reader. Raw bytes mostly die in libzip's archive checks, so an input
// whose first byte is odd is taken as the model XML instead and zipped here (stored, with the
// standard relationships part), which lets the fuzzer reach the XML scanner and the object,
// component and build-item logic.
#include <zip.h>

#include <string>

#include "fuzz_common.hpp"

namespace {

// A 3MF archive holding `model` as 3D/3dmodel.model; empty if libzip fails.
std::string zip_model(std::string_view model) {
    static const std::string rels =
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        "<Relationships xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\">"
        "<Relationship Target=\"/3D/3dmodel.model\" Id=\"rel0\" "
        "Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/>"
        "</Relationships>\n";
    zip_error_t error;
    zip_error_init(&error);
    zip_source_t* out = zip_source_buffer_create(nullptr, 0, 0, &error);
    zip_error_fini(&error);
    if (!out) return {};
    zip_source_keep(out);
    std::string result;
    zip_t* z = zip_open_from_source(out, ZIP_TRUNCATE, nullptr);
    if (z) {
        zip_source_t* a = zip_source_buffer(z, rels.data(), rels.size(), 0);
        zip_source_t* b = zip_source_buffer(z, model.data(), model.size(), 0);
        const zip_int64_t ia = a ? zip_file_add(z, "_rels/.rels", a, 0) : -1;
        if (ia < 0 && a) zip_source_free(a);
        const zip_int64_t ib = b ? zip_file_add(z, "3D/3dmodel.model", b, 0) : -1;
        if (ib < 0 && b) zip_source_free(b);
        bool ok = ia >= 0 && ib >= 0;
        // Stored, not deflated: compressing every input would dominate the run time.
        ok = ok && zip_set_file_compression(z, zip_uint64_t(ia), ZIP_CM_STORE, 0) == 0 &&
             zip_set_file_compression(z, zip_uint64_t(ib), ZIP_CM_STORE, 0) == 0;
        ok = ok && zip_close(z) == 0;
        if (!ok) zip_discard(z);
        if (ok && zip_source_open(out) == 0) {
            zip_stat_t st;
            zip_stat_init(&st);
            if (zip_source_stat(out, &st) == 0 && (st.valid & ZIP_STAT_SIZE)) {
                result.resize(st.size);
                if (zip_source_read(out, result.data(), st.size) != zip_int64_t(st.size))
                    result.clear();
            }
            zip_source_close(out);
        }
    }
    zip_source_free(out);
    return result;
}

// read_3mf takes the archive's bytes to free them once the model is unpacked.
void read_copy(std::string_view d, const std::string& path, carve::Mesh& mesh,
               carve::MeshReport& report) {
    std::string archive(d);
    carve::detail::read_3mf(archive, path, mesh, report);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    if ((data[0] & 1) == 0) return carve::fuzz::run_reader(data, size, read_copy);
    const std::string archive =
        zip_model(std::string_view(reinterpret_cast<const char*>(data) + 1, size - 1));
    if (archive.empty()) return 0;
    return carve::fuzz::run_reader(reinterpret_cast<const uint8_t*>(archive.data()), archive.size(),
                                   read_copy);
}
