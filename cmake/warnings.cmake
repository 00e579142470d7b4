# One set of warnings for every target: link vfsd::warnings PRIVATE. The dev
# preset turns them into errors (VFSD_WERROR=ON); CI builds it (scripts/test --all).
option(VFSD_WERROR "Treat warnings as errors (preset dev)" OFF)
add_library(vfsd_warnings INTERFACE)
add_library(vfsd::warnings ALIAS vfsd_warnings)
target_compile_options(vfsd_warnings INTERFACE -Wall -Wextra -Wpedantic $<$<BOOL:${VFSD_WERROR}>:-Werror>)
