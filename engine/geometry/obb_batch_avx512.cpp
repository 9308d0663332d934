// testBoxPairs' AVX-512 form (F, VL, BW, DQ): the kernel of obb_batch_kernel.h 16 lanes at a time,
// with 32 vector registers (the AVX2 form spills about a third of its values to the stack). The
// pairs are gathered 8 lanes at a time as in the AVX2 form: a 16-lane gather with 64-byte loads
// (two per box, the second masked) was tried and cost more in `query overlap` (31-37 ns a pair
// against 17-27 for this file's form, in runs beside a compile; 15-16 on a quiet machine), the
// boxes' records 272 bytes apart, so most 64-byte loads cross a cache line.
// So was a form that sends only the lanes stage 1 leaves open on to stages 2 and 3, 16 at a time
// (compressed into a queue): 22 ns a pair against 14 on pairs half of which overlap, 15-16 against
// 14-15 on sparse ones (the later stages are not where a block's time goes; the gather is).
// This file alone is compiled with the AVX-512 flags, where CMake defines NESTWALK_OBB_BATCH_AVX512
// (engine/CMakeLists.txt); obb_batch.cpp calls it only where the processor has those extensions
// (obbBatchKernel). It defines only its entry point (the kernel has internal linkage and calls no
// other header's inline function), so nothing compiled here can be picked by the linker for the
// portable build's code: ObbBatch.Avx512FileDefinesOnlyItsEntryPoint checks the object.
#include "nestwalk/geometry/obb_batch_kernel.h"

#ifdef NESTWALK_OBB_BATCH_AVX512
#if !defined(__AVX512F__) || !defined(__AVX512VL__) || !defined(__AVX512BW__) || !defined(__AVX512DQ__)
#error "obb_batch_avx512.cpp is compiled with -mavx512f -mavx512vl -mavx512bw -mavx512dq (engine/CMakeLists.txt)"
#endif

namespace nestwalk::obb_batch_detail {

std::size_t boxPairsAvx512(const BoxPairsView& pairs, NestedResult* out) {
  return pairs.orthonormalAxes ? boxPairBlocks<v16f, v16i, false>(pairs, out, gatherBlockAvx2)
                               : boxPairBlocks<v16f, v16i, true>(pairs, out, gatherBlockAvx2);
}

}  // namespace nestwalk::obb_batch_detail
#endif
