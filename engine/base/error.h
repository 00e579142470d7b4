#pragma once
// The engine's typed errors. Every failure the user can cause ends in one of these,
// with a one-line message that names the file (and the line for text formats).

#include <stdexcept>
#include <string>

namespace vfsd {

// Base of all vfsd errors.
struct Error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The input (a mesh file, a scene, a region, a curve) is malformed or unusable.
struct InputError : Error {
    using Error::Error;
};

// Reading or writing a file failed at the operating-system level.
struct IoError : Error {
    using Error::Error;
};

// The numerical method failed (e.g. a non-finite position during integration).
struct NumericalError : Error {
    using Error::Error;
};

}  // namespace vfsd
