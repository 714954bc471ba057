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
#include <vector>

#include "support/sanitizers.hpp"
#include "support/scratch.hpp"

namespace carve::test {

struct CarveRun {
    int status = -1;  // exit status, or 128 + signal
    std::string out, err;
};

// A folder of this test program's own (its process id in the name), made on first use and
// removed at its end.
inline std::filesystem::path scratch() {
    static const ScratchDir dir("carve_test_");
    return dir.path();
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

// In a forked child: becomes `carve ARGS`.
[[noreturn]] inline void exec_carve(const std::vector<std::string>& args) {
    std::vector<char*> argv{const_cast<char*>(CARVE_BINARY)};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(CARVE_BINARY, argv.data());
    ::_exit(127);
}

// A carve run started in the background, once its first progress line is out (a tenth of the
// layers through the pipeline): a signal sent then lands mid-run however fast the machine. Its
// stderr stays open until wait(), which reaps it: a write to a closed pipe would end it first.
struct RunningCarve {
    pid_t pid = -1;
    int progress = -1;  // the read end of carve's stderr
    std::string seen;   // what it printed before it was handed back
    int wait() {
        int status = 0;
        if (pid > 0) ::waitpid(pid, &status, 0);
        if (progress >= 0) ::close(progress);
        pid = -1, progress = -1;
        return status;
    }
};

inline RunningCarve start_carve(const std::vector<std::string>& args) {
    RunningCarve run;
    int err[2];
    if (::pipe(err) != 0) return run;
    run.pid = ::fork();
    if (run.pid == 0) {
        if (!std::freopen("/dev/null", "w", stdout) || ::dup2(err[1], 2) < 0) ::_exit(126);
        ::close(err[0]);
        ::close(err[1]);
        exec_carve(args);
    }
    ::close(err[1]);
    run.progress = err[0];
    char buf[256];
    for (ssize_t n; run.seen.find(" layers") == std::string::npos &&
                    (n = ::read(run.progress, buf, sizeof buf)) > 0;)
        run.seen.append(buf, size_t(n));
    return run;
}

inline int lines(const std::string& s) {
    int n = 0;
    for (char c : s) n += c == '\n';
    return n;
}

}  // namespace carve::test
