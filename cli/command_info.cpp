#include "base/error.h"
#include "cli/commands.h"

namespace vfsd::cli {

int run_info(const Args&) { throw vfsd::Error("'info' is not built yet"); }

}  // namespace vfsd::cli
