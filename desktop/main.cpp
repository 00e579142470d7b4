// vfsd-desktop [--scene FILE] [--script FILE] [--exit-after-script] [--backend auto|cpu|gpu]
//              [--antialias auto|on|off] [--size WxH] [MESH]
//
// The desktop editor: opens MESH (a mesh file or builtin:NAME) or the scene FILE,
// or the built-in default scene, and runs the script's actions (docs/desktop.md).
// A changed session is autosaved; started without a file after a crash, the editor
// offers to restore it (docs/robustness.md, "Nothing lost").

#include <cstdio>
#include <cstring>
#include <string>

#include "base/heap.h"
#include "desktop/app.h"

namespace {

void usage(std::FILE* out) {
    std::fputs("usage: vfsd-desktop [--scene FILE] [--script FILE] [--exit-after-script] [--backend auto|cpu|gpu]\n"
               "                    [--antialias auto|on|off] [--size WxH] [MESH]\n"
               "Opens MESH (.obj .off .ply .stl .gltf .glb or builtin:NAME), the scene FILE, or the default\n"
               "scene; F1 in the window lists the shortcuts. docs/desktop.md describes scripts.\n"
               "--antialias: multisample the view (auto: unless the renderer is a software one).\n"
               "The session is autosaved to $VFSD_AUTOSAVE_DIR, else $XDG_STATE_HOME/vfsd/autosave,\n"
               "else ~/.local/state/vfsd/autosave; a start without a file offers to restore it.\n",
               out);
}

}  // namespace

int main(int argc, char** argv) {
    vfsd::keep_freed_memory();  // base/heap.h
    vfsd::desktop::AppOptions options;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        const auto value = [&](const char* name) -> std::string {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "vfsd-desktop: %s needs a value\n", name);
                std::exit(2);
            }
            return argv[++i];
        };
        if (arg == "--scene") options.scene = value("--scene");
        else if (arg == "--script") options.script = value("--script");
        else if (arg == "--exit-after-script") options.exit_after_script = true;
        else if (arg == "--backend") options.backend = value("--backend");
        else if (arg == "--antialias") options.antialias = value("--antialias");
        else if (arg == "--size") {
            if (std::sscanf(value("--size").c_str(), "%dx%d", &options.width, &options.height) != 2 ||
                options.width < 64 || options.height < 64) {
                std::fprintf(stderr, "vfsd-desktop: --size expects WxH, e.g. 1280x800\n");
                return 2;
            }
        } else if (arg == "-h" || arg == "--help") {
            usage(stdout);
            return 0;
        } else if (!arg.empty() && arg[0] == '-') {
            std::fprintf(stderr, "vfsd-desktop: unknown option '%s'\n", arg.c_str());
            usage(stderr);
            return 2;
        } else {
            options.mesh = arg;
        }
    }
    if (options.backend != "auto" && options.backend != "cpu" && options.backend != "gpu") {
        std::fprintf(stderr, "vfsd-desktop: --backend must be auto, cpu or gpu\n");
        return 2;
    }
    if (options.antialias != "auto" && options.antialias != "on" && options.antialias != "off") {
        std::fprintf(stderr, "vfsd-desktop: --antialias must be auto, on or off\n");
        return 2;
    }
    try {
        vfsd::desktop::App app(options);
        return app.run();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "vfsd-desktop: %s\n", e.what());
        return 1;
    }
}
