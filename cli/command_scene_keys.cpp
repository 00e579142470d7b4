// vfsd scene-keys: the keys of a scene file, what each takes and its default
// (engine/scene/scene.h, scene_keys(); docs/scene-format.md has the details).

#include <cstdio>

#include "cli/commands.h"
#include "scene/scene.h"

namespace vfsd::cli {

int run_scene_keys(const Args& args) {
    args.expect({}, 0, 0);
    for (const SceneKey& key : scene_keys())
        std::printf("%-16s %s\n%-16s default: %s\n", key.name, key.value, "", key.default_value);
    std::printf("\nRegion kinds, selectors and the report's fields: docs/scene-format.md.\n");
    return kExitOk;
}

}  // namespace vfsd::cli
