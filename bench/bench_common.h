// bench/bench_common.h: what the files of aniso_bench share. bench_eval.cpp holds the inputs, the
// materials and main(); the other files register their benchmarks and checks, which main() calls.
#pragma once

#include <span>
#include <string>

#include "aniso/brdf/material.h"

// bench_eval.cpp: the kPairs precomputed (wi, wo) pairs above the horizon and the benchmarked
// materials by key ("ward/vector/balanced", "metal/gold", ...).
std::span<const aniso::Vec3> bench_wi();
std::span<const aniso::Vec3> bench_wo();
const aniso::Material& bench_material(const std::string& key);

// bench_sample.cpp: sample and pdf throughput; check_sample returns the number of failures.
void register_sample_benchmarks();
int check_sample();
// bench_batch.cpp: the batch API; check_batch returns the number of failures.
void register_batch_benchmarks();
int check_batch();
// bench_rgl.cpp: RGL tensor files read back.
void register_rgl_benchmarks();
