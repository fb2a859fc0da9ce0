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

}  // namespace meshtour
