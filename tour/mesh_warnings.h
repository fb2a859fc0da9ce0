#pragma once
// Messages about the model that the commands computing a path share: errors of the path stages
// prefixed with the model's file, and the warning for flat models.
#include <string>
#include <utility>

#include "core/error.h"
#include "mesh/mesh.h"

namespace meshtour {

/// Runs `compute` (a path computation on the model of `file`); an InputError it throws is
/// rethrown with the file's name in front, so that the one-line message says which file to fix.
template <typename Compute>
auto with_file_name(const std::string& file, Compute&& compute) {
  try {
    return std::forward<Compute>(compute)();
  } catch (const InputError& e) {
    throw InputError(file + ": " + e.what());
  }
}

/// Prints a warning on stderr when the model is flat: seen along its plane (which contains the
/// up direction `up`), the tour shows it edge-on twice per loop. A plane across the up direction
/// never gets here: the path stages refuse it, suggesting another --up.
void warn_if_flat(const TriangleMesh& mesh, const Eigen::Vector3d& up, const std::string& file);

}  // namespace meshtour
