// carve's error types and the exit status each one maps to. Bottom layer: depends on nothing
// else of carve. Every failure that reaches the user is one of these, so that main() can turn
// it into one line on stderr and a documented exit status (README, docs/carve.1):
//   0 success, 1 bad input or bad option value (also a refused input: over a resource guard or
//   the --timeout), 2 usage (unknown option, missing argument), 3 an output could not be
//   written or was refused (the input itself, another output of the run, a device), 4 internal
//   failure (a bug, or out of memory), 5 `carve check --strict` (or `carve slice --strict`):
//   the G-code fails a printability rule (it was read and measured; the rules failed are on
//   stderr, and slice writes nothing).
#pragma once

#include <stdexcept>
#include <string>

namespace carve {

enum ExitCode : int {
    kExitOk = 0,
    kExitBadInput = 1,
    kExitUsage = 2,
    kExitOutput = 3,
    kExitInternal = 4,
    kExitRuleFailed = 5,
};

// The message as a terminal can show it whole: a NUL (which ended what() there: "found '")
// or another control byte that a broken file's token or a file name put in it is written as
// \xNN. Line feeds and tabs stay.
inline std::string printable_message(const std::string& message) {
    static const char* const kHex = "0123456789abcdef";
    std::string out;
    out.reserve(message.size());
    for (const char c : message) {
        const auto u = static_cast<unsigned char>(c);
        if ((u < 0x20 && c != '\n' && c != '\t') || u == 0x7f) {
            out += "\\x";
            out += kHex[u >> 4];
            out += kHex[u & 15];
        } else {
            out += c;
        }
    }
    return out;
}

// Base of the errors carve reports in words; what() is the whole message.
struct CarveError : std::runtime_error {
    explicit CarveError(const std::string& message)
        : std::runtime_error(printable_message(message)) {}
    explicit CarveError(const char* message) : CarveError(std::string(message)) {}
    virtual int exit_code() const = 0;
};

// A bad input file, option or profile value, or an input refused by a resource guard.
struct InputError : CarveError {
    using CarveError::CarveError;
    int exit_code() const override { return kExitBadInput; }
};

// The command line itself is malformed (unknown option, missing argument).
struct UsageError : CarveError {
    using CarveError::CarveError;
    int exit_code() const override { return kExitUsage; }
};

// An output could not be written (disk full, no permission) or is refused (it would replace
// the input or another output of the run, or it is not a regular file).
struct OutputError : CarveError {
    using CarveError::CarveError;
    int exit_code() const override { return kExitOutput; }
};

// The G-code made fails a printability rule of `carve check --strict` (carve slice --strict):
// nothing is written.
struct RuleError : CarveError {
    using CarveError::CarveError;
    int exit_code() const override { return kExitRuleFailed; }
};

}  // namespace carve
