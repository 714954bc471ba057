// M73 lines put into the body as it is copied (progress.hpp).
#include "gcode/progress.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>

#include "base/error.hpp"

namespace carve {

namespace {

// Percent done (rounded down, 100 only at the end) and minutes left (rounded).
std::pair<long long, long long> progress_figures(ProgressTime t) {
    const double left = std::max(0.0, t.total_s - t.elapsed_s);
    long long percent = 100;
    if (t.total_s > 0 && t.elapsed_s < t.total_s)
        percent = std::clamp<long long>(std::llround(std::floor(100.0 * t.elapsed_s / t.total_s)),
                                        0, 100);
    return {percent, std::llround(left / 60.0)};
}

}  // namespace

std::string m73_line(ProgressTime normal, const ProgressTime* stealth) {
    const auto [percent, minutes] = progress_figures(normal);
    if (!stealth) return fmt::format("M73 P{} R{}\n", percent, minutes);
    const auto [q, s] = progress_figures(*stealth);
    return fmt::format("M73 P{} R{}\nM73 Q{} S{}\n", percent, minutes, q, s);
}

void copy_with_progress(const std::vector<std::FILE*>& bodies, std::FILE* out,
                        const std::vector<ProgressMark>& marks, double total_s,
                        const std::string& path, double stealth_total_s) {
    auto fail = [&] { throw OutputError("cannot write " + path + ": " + std::strerror(errno)); };
    // 64 KB: a megabyte zeroed here was 256 fresh pages in the serial end of every run.
    std::vector<char> chunk(1 << 16);
    long long at = 0;  // body bytes copied so far
    size_t next = 0;   // the next mark to write
    std::string last;  // the line written last: the same figures are not repeated
    auto progress = [&](const ProgressMark& mark) {
        const ProgressTime stealth{mark.stealth_elapsed_s, stealth_total_s};
        const std::string line =
            m73_line({mark.elapsed_s, total_s}, stealth_total_s >= 0 ? &stealth : nullptr);
        if (line == last) return;
        if (std::fwrite(line.data(), 1, line.size(), out) != line.size()) fail();
        last = line;
    };
    for (std::FILE* body : bodies) {
        for (size_t n; (n = std::fread(chunk.data(), 1, chunk.size(), body)) > 0;) {
            size_t done = 0;
            while (done < n) {
                const long long chunk_end = at + static_cast<long long>(n - done);
                if (next < marks.size() && marks[next].offset < chunk_end) {
                    const size_t upto = static_cast<size_t>(std::max(0LL, marks[next].offset - at));
                    if (upto > 0 && std::fwrite(chunk.data() + done, 1, upto, out) != upto) fail();
                    done += upto;
                    at += static_cast<long long>(upto);
                    progress(marks[next]);
                    ++next;
                    continue;
                }
                const size_t rest = n - done;
                if (std::fwrite(chunk.data() + done, 1, rest, out) != rest) fail();
                done = n;
                at = chunk_end;
            }
        }
        if (std::ferror(body)) fail();
    }
    for (; next < marks.size(); ++next) progress(marks[next]);  // at the very end
}

}  // namespace carve
