// The one exception type that reaches the user: a bad input file or a bad option.
// The CLI prints its message as a single line on stderr and exits with status 1.
#pragma once

#include <stdexcept>
#include <string>

namespace carve {

struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

}  // namespace carve
