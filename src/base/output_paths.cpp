// Output path checks (see output_paths.hpp).
#include "base/output_paths.hpp"

#include <fmt/format.h>
#include <sys/stat.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "base/errors.hpp"

namespace carve {

namespace {

// Identity of the file a path names: "dev:ino" when it exists, its canonical spelling otherwise.
std::string identity(const std::string& path) {
    struct stat st {};
    // snprintf, not string concatenation: GCC 12 at -O3 warns (-Wrestrict, a false positive)
    // on "i" + std::to_string(...) and on appending to a one-character string.
    if (::stat(path.c_str(), &st) == 0) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "i%ju:%ju", static_cast<std::uintmax_t>(st.st_dev),
                      static_cast<std::uintmax_t>(st.st_ino));
        return buf;
    }
    std::error_code ec;
    const std::filesystem::path c = std::filesystem::weakly_canonical(path, ec);
    std::string id =
        ec ? std::filesystem::absolute(path, ec).lexically_normal().string() : c.string();
    id.insert(id.begin(), 'p');
    return id;
}

// Under /dev, /proc or /sys as spelled or once resolved: /dev/stdout resolves to whatever
// stdout is (a terminal, a pipe, or a regular file that rename would then replace).
bool special_prefix(const std::string& path) {
    std::error_code ec;
    const std::string spelled = std::filesystem::absolute(path, ec).lexically_normal().string();
    const std::string resolved = std::filesystem::weakly_canonical(path, ec).string();
    for (const std::string& c : {spelled, resolved})
        for (const char* p : {"/dev/", "/proc/", "/sys/"})
            if (c.rfind(p, 0) == 0) return true;
    return false;
}

}  // namespace

void check_output_paths(const std::vector<NamedPath>& inputs,
                        const std::vector<NamedPath>& outputs) {
    std::vector<std::pair<std::string, const NamedPath*>> seen;
    for (const NamedPath& in : inputs)
        if (!in.path.empty()) seen.emplace_back(identity(in.path), &in);
    for (const NamedPath& out : outputs) {
        if (out.path.empty()) continue;
        struct stat st {};
        if (::stat(out.path.c_str(), &st) == 0) {
            if (out.folder && !S_ISDIR(st.st_mode))
                throw OutputError(out.what + " " + out.path + ": exists and is not a folder");
            if (!out.folder && !S_ISREG(st.st_mode))
                throw OutputError(out.what + " " + out.path +
                                  ": exists and is not a regular file (carve writes only "
                                  "regular files, never onto a device or special file)");
        }
        // /dev/stdout and friends resolve to whatever stdout is; never a place for an output.
        if (special_prefix(out.path))
            throw OutputError(out.what + " " + out.path +
                              ": is under /dev, /proc or /sys (carve writes only regular files)");
        const std::string id = identity(out.path);
        for (const auto& [other_id, other] : seen)
            if (other_id == id)
                throw OutputError(out.what + " " + out.path + " is the same file as " +
                                  other->what + " " + other->path +
                                  "; refusing to overwrite it (choose another name)");
        seen.emplace_back(id, &out);
    }
}

}  // namespace carve
