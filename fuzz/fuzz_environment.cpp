// Fuzz target: the environment image reader (tracer/environment.h: read_environment, after
// OpenImageIO's decoders). The first byte picks the extension (.hdr, .exr, .png), the rest is the
// file. Any meshtour::Error is a correct answer; an image it accepts must be 2:1 and hold finite,
// non-negative values.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <fstream>

#include "core/error.h"
#include "fuzz_scratch.h"
#include "tracer/environment.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const meshtour::fuzz::ScratchDir scratch("fuzz-environment");
  static const char* const names[] = {"input.hdr", "input.exr", "input.png"};
  const auto file = scratch.dir / names[data[0] % 3];
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  try {
    const meshtour::EnvironmentImage env = meshtour::read_environment(file);
    if (env.width <= 0 || env.height <= 0 || env.rgb.size() != static_cast<std::size_t>(env.width) * env.height * 3) __builtin_trap();
    for (const float v : env.rgb)
      if (!(v >= 0.0f) || !std::isfinite(v)) __builtin_trap();
  } catch (const meshtour::Error&) {
  }
  return 0;
}
