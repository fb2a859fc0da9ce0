#pragma once
// The instruction sets the renderer's hot loops are compiled for. The tile kernel
// (tile_kernel.cpp) and the denoiser's passes (denoiser_pass.cpp) are each one template,
// specialised once per set by compiling the file once per set (tracer/CMakeLists.txt); the
// renderer runs the widest the CPU has (the variable MESHTOUR_TILE_KERNEL=baseline|x86-64-v3|
// x86-64-v4 forces one). Every copy gives the same bits (simd.h says why).
namespace meshtour {

enum class InstructionSet { baseline, x86_64_v3, x86_64_v4 };

// The set the including file is compiled for: tracer/CMakeLists.txt names it for the wider
// copies; the baseline copy is compiled with the project's own flags. (A const variable: each
// file has its own.)
#ifndef MESHTOUR_INSTRUCTION_SET
#define MESHTOUR_INSTRUCTION_SET baseline
#endif
constexpr InstructionSet kCompiledFor = InstructionSet::MESHTOUR_INSTRUCTION_SET;

// Whether this CPU runs code compiled for `set`. GCC names the levels; Clang 14 knows neither
// them nor F16C and MOVBE, so there the levels are their other features (every CPU with AVX2,
// FMA and BMI2 has F16C and MOVBE too).
inline bool cpu_runs(InstructionSet set) {
  if (set == InstructionSet::baseline) return true;
#if defined(__x86_64__)
  __builtin_cpu_init();
#if defined(__clang__)
  const bool v3 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi") &&
                  __builtin_cpu_supports("bmi2");
  const bool v4 = v3 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
                  __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("avx512dq") &&
                  __builtin_cpu_supports("avx512vl");
#else
  const bool v3 = __builtin_cpu_supports("x86-64-v3"), v4 = __builtin_cpu_supports("x86-64-v4");
#endif
  return set == InstructionSet::x86_64_v3 ? v3 : v4;
#else
  return false;
#endif
}

}  // namespace meshtour
