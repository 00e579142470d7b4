// Every input the fuzzers ever crashed on (fuzz/regressions/<target>/) and every
// seed (fuzz/corpus/<target>/) replays through the same code as the libFuzzer
// targets (fuzz/fuzz_input.h): it must parse or throw vfsd::Error, never crash or
// throw anything else. The seeds are valid files and must parse.

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "../fuzz/fuzz_input.h"

namespace fs = std::filesystem;

namespace {

std::vector<fs::path> files_in(const fs::path& folder) {
    std::vector<fs::path> files;
    std::error_code ec;
    if (!fs::is_directory(folder, ec)) return files;
    for (const auto& entry : fs::directory_iterator(folder))
        if (entry.is_regular_file() && entry.path().filename().string()[0] != '.') files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    return files;
}

std::string bytes_of(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

const fs::path kFuzzDir = fs::path(VFSD_SOURCE_DIR) / "fuzz";

}  // namespace

TEST_CASE("fuzz regression inputs parse or throw vfsd::Error", "[fuzz][hostile]") {
    for (const std::string& target : vfsd::fuzz::fuzz_targets()) {
        for (const fs::path& file : files_in(kFuzzDir / "regressions" / target)) {
            INFO(file.string());
            const std::string bytes = bytes_of(file);
            try {
                vfsd::fuzz::run_fuzz_input(target, bytes);
            } catch (const vfsd::Error& e) {
                CHECK(std::string(e.what()).find('\n') == std::string::npos);  // one-line messages
            }
        }
    }
}

TEST_CASE("fuzz seed corpora are valid inputs", "[fuzz]") {
    for (const std::string& target : vfsd::fuzz::fuzz_targets()) {
        const std::vector<fs::path> seeds = files_in(kFuzzDir / "corpus" / target);
        CHECK(seeds.size() >= 3);
        for (const fs::path& file : seeds) {
            INFO(file.string());
            CHECK_NOTHROW(vfsd::fuzz::run_fuzz_input(target, bytes_of(file)));
        }
    }
}
