// `vfsd bench --quick` runs end to end and writes one data line per model with
// positive timings and a volume error it measured; `vfsd bench --picking` runs.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "test_io_support.h"

TEST_CASE("vfsd bench --quick writes its table and data", "[bench][cli]") {
    vfsd::test::ScratchDir dir;
    const std::string command = std::string("'") + VFSD_CLI_PATH + "' bench --quick --no-gpu --data '" +
                                dir.file("bench.dat") + "' --markdown '" + dir.file("table.md") + "' >/dev/null";
    REQUIRE(std::system(command.c_str()) == 0);
    std::ifstream data(dir.file("bench.dat"));
    std::string line;
    int rows = 0;
    while (std::getline(data, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream fields(line);
        double vertices = 0, cpu1 = 0, cpu = 0, gpu = 0;
        fields >> vertices >> cpu1 >> cpu >> gpu;
        CHECK(vertices > 100);
        CHECK(cpu1 > 0.0);
        CHECK(cpu > 0.0);
        CHECK(gpu == -1.0);  // --no-gpu
        ++rows;
    }
    CHECK(rows == 2);
    std::ifstream table(dir.file("table.md"));
    std::stringstream text;
    text << table.rdbuf();
    CHECK(text.str().find("| box |") != std::string::npos);
}

TEST_CASE("vfsd bench --picking runs and its hierarchy agrees with the loop", "[bench][cli]") {
    // Exit 0 only when every sampled pick through the hierarchy equals the loop's.
    const std::string command = std::string("'") + VFSD_CLI_PATH + "' bench --picking --mesh builtin:sphere:4 --rays 200 >/dev/null";
    CHECK(std::system(command.c_str()) == 0);
}

TEST_CASE("vfsd bench --busy runs beside a busy process and ends it", "[bench][cli]") {
    vfsd::test::ScratchDir dir;
    const std::string command = std::string("'") + VFSD_CLI_PATH + "' bench --quick --no-gpu --busy --data '" +
                                dir.file("bench.dat") + "' >'" + dir.file("out.txt") + "'";
    REQUIRE(std::system(command.c_str()) == 0);
    std::ifstream out(dir.file("out.txt"));
    std::stringstream text;
    text << out.rdbuf();
    CHECK(text.str().find("a busy process runs beside the bench") != std::string::npos);
    // The busy child (a fork: the same command line) is gone once the bench is.
    const std::string left = std::string("pgrep -x -f -- '") + VFSD_CLI_PATH +
                             " bench --quick --no-gpu --busy --data " + dir.file("bench.dat") + "' >/dev/null";
    CHECK(std::system(left.c_str()) != 0);
}
