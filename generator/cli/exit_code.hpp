// The one place where an error becomes a message on stderr and an exit code (README "Exit codes",
// core/errors.hpp): "clever-support: error: <what>" and the code of its kind; a CLI11 parse error
// and a ParameterError get a hint or a full stop, an ExternalToolError the tool's log after it.
//
// Example:
//   try { ... } catch (...) { return exit_code_for(std::current_exception()); }
//   // a thrown InputError("m.stl: not a mesh ...") prints "clever-support: error: m.stl: ..." and gives 3
#pragma once

#include <exception>

namespace cs {

int exit_code_for(const std::exception_ptr& error);

}  // namespace cs
