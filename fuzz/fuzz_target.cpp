// One libFuzzer target (VFSD_FUZZ_TARGET: obj, off, ply, stl, gltf or scene; see
// fuzz_input.h). An input may parse or throw vfsd::Error; a crash, a sanitizer
// report, a leak or any other exception is a finding.

#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        vfsd::fuzz::run_fuzz_input(VFSD_FUZZ_TARGET, std::string(reinterpret_cast<const char*>(data), size));
    } catch (const vfsd::Error&) {
    }
    return 0;
}
