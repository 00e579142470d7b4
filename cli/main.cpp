// vfsd: the command-line front end of the engine.
// Exit codes: 0 ok, 1 bad input, 2 bad usage.

#include <cstdio>
#include <cstring>
#include <string>

#include "base/error.h"
#include "base/heap.h"
#include "cli/commands.h"

namespace {

void print_usage(std::FILE* out) {
    std::fprintf(out,
                 "usage: vfsd <command> [options]\n"
                 "\n"
                 "Volume-preserving, foldover-free mesh deformation along vector fields\n"
                 "(von Funck, Theisel, Seidel: Explicit Control of Vector Field Based Shape Deformations).\n"
                 "\n"
                 "commands:\n");
    for (const vfsd::cli::Command& c : vfsd::cli::commands()) std::fprintf(out, "  %-9s %s\n", c.name, c.summary);
    std::fprintf(out, "\nRun 'vfsd <command> --help' for the options of a command.\n");
}

}  // namespace

int main(int argc, char** argv) {
    vfsd::keep_freed_memory();  // base/heap.h
    using namespace vfsd::cli;
    if (argc < 2) {
        print_usage(stderr);
        return kExitUsage;
    }
    const std::string name = argv[1];
    if (name == "--help" || name == "-h" || name == "help") {
        print_usage(stdout);
        return kExitOk;
    }
    for (const Command& c : commands()) {
        if (name != c.name) continue;
        try {
            Args args(c.name, argc - 2, argv + 2);
            if (args.wants_help()) {
                std::fputs(c.help, stdout);
                return kExitOk;
            }
            return c.run(args);
        } catch (const UsageError& e) {
            std::fprintf(stderr, "vfsd %s: %s (see 'vfsd %s --help')\n", c.name, e.what(), c.name);
            return kExitUsage;
        } catch (const vfsd::Error& e) {
            std::fprintf(stderr, "vfsd %s: %s\n", c.name, e.what());
            return kExitInput;
        } catch (const std::exception& e) {
            std::fprintf(stderr, "vfsd %s: internal error: %s\n", c.name, e.what());
            return kExitInput;
        }
    }
    std::fprintf(stderr, "vfsd: unknown command '%s' (see 'vfsd --help')\n", name.c_str());
    return kExitUsage;
}
