// libFuzzer target: the OBJ reader, fed any text.
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return carve::fuzz::run_reader(data, size, carve::detail::read_obj);
}
