#pragma once
// OpenMesh prints its warnings (non-manifold faces it had to split off, parse errors) to its own
// process-wide streams, which default to std::cerr. meshtour routes them into a buffer instead, so
// they reach the user through reports, not in the middle of a progress display.
#include <mutex>
#include <string>
#include <vector>

namespace meshtour {

/// While alive, collects what OpenMesh prints; holds a process-wide lock (OpenMesh's IO manager
/// and log streams are singletons), so only one capture runs at a time.
class OpenMeshLogCapture {
public:
  OpenMeshLogCapture();
  ~OpenMeshLogCapture();
  OpenMeshLogCapture(const OpenMeshLogCapture&) = delete;
  OpenMeshLogCapture& operator=(const OpenMeshLogCapture&) = delete;

  /// The non-empty lines printed since the capture began.
  std::vector<std::string> lines() const;

private:
  std::unique_lock<std::mutex> lock_;
};

}  // namespace meshtour
