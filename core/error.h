#pragma once
// The exceptions every meshtour library throws. Messages are written for the user: they name the
// file or option at fault and say what to change. The CLI prints what() on one line and maps the
// type to an exit code.
#include <stdexcept>
#include <string>

namespace meshtour {

/// Base of all meshtour errors.
class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// Bad input from the user: an option out of range, a mesh that cannot be used, a bad scene file.
class InputError : public Error {
public:
  using Error::Error;
};

/// A file could not be read or written (missing, unreadable, unwritable, disk full).
class IoError : public Error {
public:
  using Error::Error;
};

/// The renderer or the video encoder failed in a library call.
class RuntimeFailure : public Error {
public:
  using Error::Error;
};

/// How a failure ends the program: its exit code and the name a batch summary gives it.
struct ExitClass {
  int code;
  const char* name;
};

/// The exit class of an error: input 2 (fix the input or the options), io 3 (a file could not be
/// read or written), runtime 4 (a library failed), unexpected 1 (anything else: a bug).
inline ExitClass exit_class_of(const std::exception& e) {
  if (dynamic_cast<const InputError*>(&e)) return {2, "input"};
  if (dynamic_cast<const IoError*>(&e)) return {3, "io"};
  if (dynamic_cast<const RuntimeFailure*>(&e)) return {4, "runtime"};
  return {1, "unexpected"};
}

}  // namespace meshtour
