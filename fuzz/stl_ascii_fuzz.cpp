// libFuzzer target: the ASCII STL reader, fed any text.
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return carve::fuzz::run_reader(data, size, carve::detail::read_ascii_stl);
}
