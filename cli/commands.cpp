#include "cli/commands.h"

namespace vfsd::cli {

const std::vector<Command>& commands() {
    static const std::vector<Command> list = {
        {"info", "print counts, topology, valence, bounding box and volume of a mesh",
         "usage: vfsd info MESH [--json]\n"
         "\n"
         "MESH is a file (.obj .off .ply .stl .gltf .glb) or builtin:NAME[:RESOLUTION]\n"
         "(NAME: box, bar, cylinder, sphere).\n"
         "Prints vertices, triangles, boundary loops, whether the mesh is manifold and\n"
         "why not, the valence histogram, the bounding box and the signed volume;\n"
         "--json prints the same as one JSON object.\n",
         run_info},
        {"convert", "convert a mesh between formats",
         "usage: vfsd convert IN OUT [--force] [--keep-layout] [--double] [--subdivide N]\n"
         "\n"
         "Reads IN (.obj .off .ply .stl .gltf .glb or builtin:NAME) and writes OUT\n"
         "(.obj .off .ply .glb), atomically. OUT must differ from IN; an existing OUT\n"
         "is replaced only with --force.\n"
         "  --keep-layout  write IN's own vertex layout instead of the welded mesh\n"
         "  --double       store PLY positions as float64\n"
         "  --subdivide N  split every triangle into four at its edge midpoints, N times\n"
         "                 (the same surface with 4^N times the triangles)\n",
         run_convert},
        {"deform", "deform a mesh as a scene file describes and report the result",
         "usage: vfsd deform SCENE.json --out OUT.{obj,off,ply,glb} [--report REPORT.json]\n"
         "                  [--steps N | --tolerance T] [--backend cpu|gpu] [--threads N] [--field-out FILE] "
         "[--force]\n"
         "\n"
         "--steps N takes N fixed RK4 steps per unit time (sec. 7.1); --tolerance T\n"
         "controls each step's estimated error to T of the bounding box diagonal (a\n"
         "scene file that gives neither: 0.0005). The report's \"step_control\" gives\n"
         "the steps rejected and the estimates, and every step tried as \"tries\":\n"
         "[t, h, estimate, taken].\n"
         "--backend gpu runs the scene's steps as fragment passes in a headless GL\n"
         "context (OSMesa), the CPU's scheme pass by pass (docs/gpu.md); when no\n"
         "context can be made vfsd exits 1 and says why. --threads limits the\n"
         "CPU backend's threads (default: all). When triangles fold, the mesh is refined\n"
         "around them at rest and the scene runs again from t = 0 (\"fold_refinement\"\n"
         "times, default 6): the result then has the (welded) input's vertices and new\n"
         "ones after them, and stderr and the report's \"refinement\" say so. When\n"
         "triangles still fold, stderr says how\n"
         "many, after which step and where; the report's \"folds\" lists them.\n"
         "'vfsd scene-keys' lists the scene file's keys and their defaults.\n",
         run_deform},
        {"scene-keys", "list the keys of a scene file, what each takes and its default",
         "usage: vfsd scene-keys\n"
         "\n"
         "Prints every top-level key of a scene file (see 'vfsd deform'), what it takes\n"
         "and its default; docs/scene-format.md describes regions, selectors and the report.\n",
         run_scene_keys},
        {"render", "render a scene (optionally deformed to a time) to a PNG, headless",
         "usage: vfsd render SCENE.json --png OUT.png [--time t] [--size WxH] [--backend cpu|gpu]\n"
         "                  [--wireframe] [--steps N] [--force]\n"
         "                  [--view front|back|right|left|top|bottom|iso] [--up z|y] [--zoom Z] [--target X,Y,Z]\n"
         "\n"
         "Draws the mesh with s from blue (0) to red (1), the region borders in yellow,\n"
         "the curve, a white sphere at c(t) and a dark one at the scene's target time;\n"
         "triangles folded at that time are drawn in magenta, as the editors draw them.\n"
         "--time integrates to t first (default 0, the undeformed scene) on the GPU\n"
         "(the default; the CPU's steps as fragment passes, docs/gpu.md) or with\n"
         "--backend cpu on the CPU; a sphere-tool region always runs on the CPU.\n"
         "--size defaults to 800x600. The camera frames the whole deformation from --view\n"
         "(default iso, a 3/4 view) with --up the axis that is up on the screen (default z;\n"
         "y for meshes modelled y-up); --zoom 4 shows a quarter as much, about --target\n"
         "(default the framed centre), so that any part, a fold say, can be looked at.\n"
         "Needs OSMesa.\n",
         run_render},
        {"bench", "time the deformation per step on the paper's models and larger meshes",
         "usage: vfsd bench [--quick] [--only TEXT] [--markdown FILE] [--data FILE] [--steps N] [--repeat N] "
         "[--no-gpu] [--busy]\n"
         "       vfsd bench --picking [--mesh SPEC] [--rays N]\n"
         "       vfsd bench --latency [--quick] [--only TEXT | --scene FILE] [--tolerance T | --steps N]\n"
         "                            [--reference-steps N] [--repeat N] [--threads N | --busy] [--no-reference]\n"
         "       vfsd bench --gpu-schemes [--only TEXT | --scene FILE] [--steps N]\n"
         "       vfsd bench --fold-tests [--mesh SPEC] [--time T] [--repeat N]\n"
         "\n"
         "Per mesh: a 45-degree bend of 250 RK4 steps (10 smoothing steps each), ms per step\n"
         "(median and spread over --repeat runs; the terminal also prints the mean) on one\n"
         "thread and on all, the GPU backend when a headless context can be made, volume\n"
         "error, flipped triangles and the deformation state's bytes per vertex. --quick\n"
         "runs two small meshes for a few steps (CI). --only runs the models whose name\n"
         "contains TEXT. --busy keeps a child process spinning on one core the whole time\n"
         "(another program at work: one thread against all, then). scripts/bench runs the\n"
         "full set and writes docs/benchmarks.md.\n"
         "\n"
         "vfsd bench --picking [--mesh SPEC] [--rays N] times picking the surface under a\n"
         "ray instead: building and refitting the bounding volume hierarchy, a pick\n"
         "through it (median over N rays, default 1000) and the loop over all triangles it\n"
         "replaces, on builtin:cylinder:707 (1M vertices) unless --mesh says otherwise.\n"
         "\n"
         "vfsd bench --latency times edit to final shape: on an open mesh, a curve edit (the\n"
         "motion built, integrated to t = 1 with error-controlled steps), the same started\n"
         "from the rest state an earlier run kept (as the editors do) and a region edit (s\n"
         "first), against N fixed steps (default 2000): the largest and 99.9th-percentile\n"
         "distance over the mesh's size, and the folds. --busy runs it beside a process\n"
         "spinning on one core, each repeat on all threads and then on one, and prints\n"
         "both and how they compare.\n"
         "\n"
         "vfsd bench --gpu-schemes times the GPU path: ms per step for sec. 5's passes, then\n"
         "with the gauge fit, the volume keeper and the fold repair added, and edit to final\n"
         "shape with error-controlled steps.\n"
         "\n"
         "vfsd bench --fold-tests times the fold repair's tests (the neighbour test alone\n"
         "and with the affine test) on vfsd bench's bend of --mesh (default the 53k\n"
         "cylinder) run to --time T (default 0.5): medians of N (default 40) on all threads\n"
         "and on one, and how many triangles each found short of the lift's target.\n",
         run_bench},
        {"battery", "deform generated scenes nobody tuned and measure folds, volume, rigidity",
         "usage: vfsd battery --out DIR [--seed N] [--count K] [--mesh-dir DIR [--any-mesh] | --mesh SPEC] [--coarse]\n"
         "                   [--worst K] [--steps N | --tolerance T [--reference-steps N [--baseline-steps M]\n"
         "                   [--reference-check]]] [--threads N] [--only INDEX] [--amplitude A]\n"
         "                   [--scheme default|paper|no-repair|no-refinement]\n"
         "\n"
         "--tolerance T takes error-controlled steps instead of 250 fixed ones; with\n"
         "--reference-steps N each scene also runs N fixed steps, and the report gives\n"
         "the largest distance between the two results and the folds of both\n"
         "(--baseline-steps M: and how far M fixed steps are from the N; --reference-check:\n"
         "and how far the N are from 2N, whether the reference itself is converged).\n"
         "Generates K scenes (default 30) from seed N (default 1): the built-in meshes at a\n"
         "coarse and a fine resolution (--coarse: coarse only) and every mesh file in\n"
         "--mesh-dir (e.g. assets/cgal) that is closed, in one piece and of 500 vertices or\n"
         "more (--any-mesh: also with borders, pinches, mixed winding or several pieces),\n"
         "or the one --mesh; each turned, scaled, moved far from the origin and sometimes\n"
         "mirrored at random; regions of every kind (geodesic, selectors, vertex lists,\n"
         "painted s) with a blend region at least 6 rings wide;\n"
         "curves of 1-3 pieces bending up to 180 degrees, handles, twists in [-180, 180],\n"
         "rotation and translation (--amplitude A in (0, 1] scales bends, twists, turns and\n"
         "moves down). Each is deformed on the CPU (--steps overrides the 250\n"
         "steps; --scheme paper runs secs. 5 and 6 as printed: \"stream_gauge\": \"paper\",\n"
         "\"smoothing\": \"tangent\", \"keep_volume\": false, \"fold_repair\": false and the\n"
         "regions' \"profile\": \"geodesic\"; --scheme no-repair the default with \"fold_repair\":\n"
         "false and \"fold_refinement\": 0, the flow alone; --scheme no-refinement the default\n"
         "with \"fold_refinement\": 0); per scene: flipped\n"
         "triangles and when the first appeared, reversed triangles (a second fold\n"
         "measure, exact for affine maps), volume error and change, outer\n"
         "displacement, inner rigid residual, ms/step, the vertices the fold repair placed\n"
         "again and how far, the runs on a mesh refined where it folded and the vertices\n"
         "they added (battery.json's \"runs\": each run made, its vertices and folds, as\n"
         "'vfsd deform' reports them). Writes DIR/battery.json,\n"
         "DIR/battery.csv and, for the K worst (default 5), DIR/worst-R-NAME.{json,ply,png}:\n"
         "'vfsd deform' on the .json reproduces the scene. --only INDEX runs scene INDEX alone.\n"
         "Exits 1 when a scene folds, moves its outer region or bends its inner region.\n",
         run_battery},
    };
    return list;
}

}  // namespace vfsd::cli
