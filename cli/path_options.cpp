#include "cli/path_options.h"

#include "core/error.h"
#include "mesh/up_axis.h"

namespace meshtour::cli {

const char* const kPaperUpHelp =
    "Up direction of the model = axis of the bounding cylinder the camera circles (I-18): "
    "x, y, z, -x, -y, -z, a vector such as 0,1,0.2, 'longest-aabb' (longest side of the "
    "bounding box), 'pca' (principal axis of the surface) or 'auto' (the side the model rests on most "
    "firmly, else y)";

CLI::Validator up_direction_validator() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        if (is_auto_up(text)) return {};  // decided on the loaded model (mesh/up_axis.h)
        try {
          UpDirection::parse(text);
        } catch (const InputError& e) {
          return e.what();
        }
        return {};
      },
      "AXIS");
}


}  // namespace meshtour::cli
