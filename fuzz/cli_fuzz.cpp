// libFuzzer target: carve's command-line parsing, the real main.cpp compiled without its
// main() and stopped before any job runs (g_parse_only): CLI11, the settings table's strict
// numbers and ranges, --bed, --cavities, presets, the final validation and the output path
// checks. The input is the arguments separated by NUL bytes. Seeds: command lines of the
// README and tests and option values taken from PrusaSlicer's profiles (fuzz/make_seeds.py).
// Every outcome must be an exit status with one line on stderr; nothing may crash.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#define CARVE_CLI_NO_MAIN
#include "../src/cli/main.cpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    // --help would fill the fuzzer's log: stdout goes nowhere. (stderr stays: libFuzzer reports
    // there; run with -close_fd_mask=2 to silence carve's own one-line errors.)
    static const bool quiet = std::freopen("/dev/null", "w", stdout) != nullptr;
    (void)quiet;
    g_parse_only = true;
    std::vector<std::string> args{"carve"};
    std::string current;
    for (size_t i = 0; i < size; ++i) {
        if (data[i] == 0) {
            args.push_back(current);
            current.clear();
        } else {
            current.push_back(static_cast<char>(data[i]));
        }
    }
    args.push_back(current);
    if (args.size() > 64) return 0;
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const int code = run(static_cast<int>(args.size()), argv.data());
    if (code < 0 || code > 4) std::abort();  // only the documented exit statuses
    return 0;
}
