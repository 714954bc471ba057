// The error types that reach the user now live in common/errors.hpp (with their exit codes);
// this header stays so that the stages' includes keep working.
#pragma once

#include "common/errors.hpp"
