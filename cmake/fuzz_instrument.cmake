# The fuzz build (SLIPFIT_FUZZ, .ci/fuzz) puts the sanitizers only where a fuzz target's work is
# done. ASan and UBSan triple a unit's compile time against plain -O0 (fit_refinement.cpp: 27 s
# against 8 s with clang 14; slippage.cpp 45 s, of which UBSan alone is 23 s), and most of the
# library (the segmentation's phases, the samplers, the neighborhoods) is linked into the fuzz
# targets through the stage registry but only its options are ever declared and validated there.
# So every unit carries libFuzzer's coverage instrumentation (guidance wherever an input goes),
# while ASan and UBSan at -O1 are on the readers, the config loader (the whole pipeline) and the
# numeric kernels the kernel fuzzer calls; the other units build at the job's -O0. The ASan suite
# (.ci/sanitize) instruments everything and replays every fuzz corpus and regression.
set(SLIPFIT_FUZZ_COVERAGE -fsanitize=fuzzer-no-link)
set(SLIPFIT_FUZZ_FLAGS -O1 -fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer)

# slipfit_fuzz_instrument_target(TARGET): every unit of TARGET sanitized, its precompiled header
# included.
function(slipfit_fuzz_instrument_target target)
  if(SLIPFIT_FUZZ)
    target_compile_options(${target} PRIVATE ${SLIPFIT_FUZZ_FLAGS})
  endif()
endfunction()

# slipfit_fuzz_instrument_units(TARGET UNITS...): TARGET's units carry coverage, and UNITS (paths
# relative to the current source directory) are sanitized too. These skip the target's
# precompiled header, which is built without the sanitizers.
function(slipfit_fuzz_instrument_units target)
  if(SLIPFIT_FUZZ)
    target_compile_options(${target} PRIVATE ${SLIPFIT_FUZZ_COVERAGE})
    set_property(SOURCE ${ARGN} APPEND PROPERTY COMPILE_OPTIONS ${SLIPFIT_FUZZ_FLAGS})
    set_property(SOURCE ${ARGN} PROPERTY SKIP_PRECOMPILE_HEADERS ON)
  endif()
endfunction()
