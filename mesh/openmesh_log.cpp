#include "mesh/openmesh_log.h"

#include <OpenMesh/Core/System/omstream.hh>

#include <iostream>
#include <sstream>

namespace meshtour {
namespace {

std::mutex& capture_mutex() {
  static std::mutex m;
  return m;
}

// Connected once for the life of the process: OpenMesh's multiplex stream does not free a target
// when it is disconnected, so connecting and disconnecting per call would leak each time.
std::ostringstream& openmesh_buffer() {
  static std::ostringstream* buffer = [] {
    auto* b = new std::ostringstream;  // lives as long as OpenMesh's streams that point to it
    omerr().disconnect(std::cerr);
    omerr().connect(*b);
    omlog().disconnect(std::clog);
    omout().disconnect(std::cout);
    return b;
  }();
  return *buffer;
}

}  // namespace

OpenMeshLogCapture::OpenMeshLogCapture() : lock_(capture_mutex()) {
  openmesh_buffer().str({});
  openmesh_buffer().clear();
}

OpenMeshLogCapture::~OpenMeshLogCapture() {
  omerr().flush();
  openmesh_buffer().str({});
}

std::vector<std::string> OpenMeshLogCapture::lines() const {
  omerr().flush();
  std::vector<std::string> out;
  std::istringstream in(openmesh_buffer().str());
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) out.push_back(line);
  return out;
}

}  // namespace meshtour
