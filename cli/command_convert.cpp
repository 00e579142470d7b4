#include "base/error.h"
#include "cli/commands.h"

namespace vfsd::cli {

int run_convert(const Args&) { throw vfsd::Error("'convert' is not built yet"); }

}  // namespace vfsd::cli
