// A library error as the command line says it: the library names what the user can change
// (Error::remedy), and this says how, with the option that does it.
#pragma once

#include <string>

#include "core/error.hpp"

namespace tincdt::cli {

// "out.ply: already exists (use --overwrite to replace it)".
std::string error_message(const Error& e);

}  // namespace tincdt::cli
