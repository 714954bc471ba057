// What the end-to-end tests share: a scratch folder per test program, reading a file whole, and
// running the carve executable through /bin/sh with its status, stdout and stderr.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace carve::test {

struct CarveRun {
    int status = -1;  // exit status, or 128 + signal
    std::string out, err;
};

// A folder of this test program's own (its process id in the name), made on first use.
inline std::filesystem::path scratch() {
    static const std::filesystem::path dir = [] {
        const auto d =
            std::filesystem::temp_directory_path() / ("carve_test_" + std::to_string(getpid()));
        std::filesystem::create_directories(d);
        return d;
    }();
    return dir;
}

inline std::string read(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Runs `carve ARGS` with no input; `prefix` goes before the command (e.g. "ulimit -f 8;").
inline CarveRun run_carve(const std::string& args, const std::string& prefix = "") {
    const auto out = scratch() / "stdout.txt", err = scratch() / "stderr.txt";
    const std::string cmd = prefix + " " + std::string(CARVE_BINARY) + " " + args + " >" +
                            out.string() + " 2>" + err.string() + " </dev/null";
    CarveRun r;
    const int raw = std::system(cmd.c_str());
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
    r.out = read(out);
    r.err = read(err);
    return r;
}

inline int lines(const std::string& s) {
    int n = 0;
    for (char c : s) n += c == '\n';
    return n;
}

}  // namespace carve::test
