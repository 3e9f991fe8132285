// The libFuzzer entry point of one target, chosen at compile time by CAUSTICA_FUZZ_TARGET
// (the namespace of its fuzz_one in fuzz_targets.h).
#include "fuzz/fuzz_targets.h"

#ifndef CAUSTICA_FUZZ_TARGET
#error "define CAUSTICA_FUZZ_TARGET as scene_loader, obj_reader or png_reader"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return caustica::fuzz::CAUSTICA_FUZZ_TARGET::fuzz_one(data, size);
}
