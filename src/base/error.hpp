// The error types that reach the user now live in base/errors.hpp (with their exit codes);
// this header stays so that the stages' includes keep working.
#pragma once

#include "base/errors.hpp"
