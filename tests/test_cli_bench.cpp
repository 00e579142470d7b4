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

TEST_CASE("vfsd bench --fold-tests times the fold tests and finds the same on every thread count", "[bench][cli]") {
    // Exit 0 only when the tests found the same triangles on all threads and on one.
    vfsd::test::ScratchDir dir;
    const std::string command = std::string("'") + VFSD_CLI_PATH +
                                "' bench --fold-tests --mesh builtin:cylinder:24 --time 1 --repeat 2 >'" +
                                dir.file("out.txt") + "'";
    REQUIRE(std::system(command.c_str()) == 0);
    std::ifstream out(dir.file("out.txt"));
    std::stringstream text;
    text << out.rdbuf();
    CHECK(text.str().find("checked triangles") != std::string::npos);
    // The jittered shape's row on one thread: its tests find short triangles, the affine test more.
    const std::size_t row = text.str().rfind("jittered");
    REQUIRE(row != std::string::npos);
    std::istringstream fields(text.str().substr(row));
    std::string shape, ms, slash;
    unsigned threads = 0;
    double neighbour_ms = 0.0, both_ms = 0.0;
    std::size_t neighbour_short = 0, both_short = 0;
    fields >> shape >> threads >> neighbour_ms >> ms >> both_ms >> ms >> neighbour_short >> slash >> both_short;
    CHECK(threads == 1);
    CHECK(neighbour_short > 0);
    CHECK(both_short >= neighbour_short);
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

TEST_CASE("vfsd bench --latency --quick runs error-controlled steps and compares them with fixed ones",
          "[bench][cli][step-control]") {
    vfsd::test::ScratchDir dir;
    const std::string command =
        std::string("'") + VFSD_CLI_PATH + "' bench --latency --quick > '" + dir.file("latency.txt") + "'";
    REQUIRE(std::system(command.c_str()) == 0);
    std::ifstream out(dir.file("latency.txt"));
    std::string line;
    bool found = false;
    while (std::getline(out, line)) {
        if (line.rfind("box bend", 0) != 0) continue;
        found = true;
        // box bend  VERTICES  REGION ms  CURVE-EDIT ms  REST-KEPT ms  REGION-EDIT ms  STEPS  REJECTED  MAX  P99.9
        // FOLDS / REF
        std::istringstream fields(line.substr(std::string("box bend").size()));
        double vertices = 0, region = -1, curve_edit = -1, rest_kept = -1, region_edit = -1, steps = 0, rejected = 0,
               max_dev = 1, p999 = 1;
        std::string ms;
        fields >> vertices >> region >> ms >> curve_edit >> ms >> rest_kept >> ms >> region_edit >> ms >> steps >>
            rejected >> max_dev >> p999;
        CHECK(vertices > 100);
        CHECK(region >= 0);
        CHECK(curve_edit > 0);
        CHECK(rest_kept > 0);              // and the bench checked that it gives the curve edit's shape
        CHECK(region_edit >= curve_edit);  // the region edit is the region, then the curve edit's work
        CHECK(steps > 0);
        CHECK(steps < 200 / 4);  // far fewer than the reference's 200
        CHECK(rejected >= 0);
        CHECK(max_dev < 2 * 5e-4);  // within twice the default tolerance of the fixed-step reference
        CHECK(p999 <= max_dev);
        CHECK(line.find("0 / 0") != std::string::npos);  // no folds, as the reference
    }
    CHECK(found);
}

TEST_CASE("vfsd bench --latency --busy times all threads and one beside a busy process", "[bench][cli]") {
    vfsd::test::ScratchDir dir;
    const std::string args = " bench --latency --quick --busy --repeat 2 --no-reference";
    const std::string command = std::string("'") + VFSD_CLI_PATH + "'" + args + " > '" + dir.file("latency.txt") + "'";
    REQUIRE(std::system(command.c_str()) == 0);
    std::ifstream out(dir.file("latency.txt"));
    std::string line, all_threads, one_thread, ratio;
    while (std::getline(out, line)) {
        if (line.rfind("box bend [1 thread]", 0) == 0)
            one_thread = line;
        else if (line.rfind("box bend [", 0) == 0)
            all_threads = line;
        else if (line.rfind("box bend ", 0) == 0 && line.find("all threads over one") != std::string::npos)
            ratio = line;
    }
    CHECK(!all_threads.empty());
    CHECK(!one_thread.empty());
    // box bend [N threads]  VERTICES  REGION ms  CURVE-EDIT ms  REST-KEPT ms ...: the same scene both ways.
    const auto fields = [](const std::string& row) {
        std::istringstream in(row.substr(row.find(']') + 1));
        double vertices = 0, region = -1, curve_edit = -1;
        std::string ms;
        in >> vertices >> region >> ms >> curve_edit;
        return std::pair{vertices, curve_edit};
    };
    CHECK(fields(all_threads).first > 100);
    CHECK(fields(all_threads).first == fields(one_thread).first);
    CHECK(fields(all_threads).second > 0);
    CHECK(fields(one_thread).second > 0);
    CHECK(ratio.find("curve edit") != std::string::npos);
    // The busy child is gone once the bench is.
    const std::string left = std::string("pgrep -x -f -- '") + VFSD_CLI_PATH + args + "' >/dev/null";
    CHECK(std::system(left.c_str()) != 0);
    // --busy compares thread counts itself.
    const std::string both = std::string("'") + VFSD_CLI_PATH + "'" + args + " --threads 1 > /dev/null 2>&1";
    CHECK(std::system(both.c_str()) != 0);
}

TEST_CASE("vfsd bench --gpu-schemes times each scheme on the GPU path and an edit to final shape",
          "[bench][cli][gpu]") {
    vfsd::test::ScratchDir dir;
    const std::string command = std::string("'") + VFSD_CLI_PATH + "' bench --gpu-schemes --steps 4 --scene '" +
                                VFSD_SOURCE_DIR + "/assets/scenes/fig04-box-bend.json' > '" + dir.file("gpu.txt") +
                                "' 2>&1";
    const int status = std::system(command.c_str());
    std::ifstream out(dir.file("gpu.txt"));
    std::stringstream text;
    text << out.rdbuf();
    if (status != 0 && text.str().find("no headless GL context") != std::string::npos) {
        WARN("no headless GL context here: " << text.str());
        return;
    }
    REQUIRE(status == 0);
    std::istringstream lines(text.str());
    std::string line;
    bool found = false;
    while (std::getline(lines, line)) {
        if (line.rfind("fig04-box-bend", 0) != 0) continue;
        found = true;
        // NAME  VERTICES  SEC5 ms  GAUGE ms  KEEPER ms  REPAIR ms (STEPS)  EDIT ms  STEPS  REJECTED
        std::istringstream fields(line.substr(std::string("fig04-box-bend").size()));
        double vertices = 0, scheme[4] = {0, 0, 0, 0}, edit = 0, steps = 0, rejected = -1;
        std::string ms, repaired;
        fields >> vertices >> scheme[0] >> ms >> scheme[1] >> ms >> scheme[2] >> ms >> scheme[3] >> ms >> repaired >>
            edit >> ms >> steps >> rejected;
        CHECK(vertices > 1000);
        for (const double m : scheme) CHECK(m > 0.0);
        CHECK(edit > 0.0);
        CHECK(steps > 0);
        CHECK(steps < 250);  // error-controlled: fewer than the scene's fixed steps
        CHECK(rejected >= 0);
    }
    CHECK(found);
}
