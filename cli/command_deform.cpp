#include "base/error.h"
#include "cli/commands.h"

namespace vfsd::cli {

int run_deform(const Args&) { throw vfsd::Error("'deform' is not built yet"); }

}  // namespace vfsd::cli
