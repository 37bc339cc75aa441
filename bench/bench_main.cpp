// SPDX-License-Identifier: MIT
// main() of the benchmark executables: says which peers were built in (Ceres or not) and which BLAS
// the process loaded (CHOLMOD's supernodal factorisation runs in it) and which 6×6 block kernels the
// temporary graph's solver uses, on stdout and in the JSON context, then runs Google Benchmark as
// BENCHMARK_MAIN would.
#include <benchmark/benchmark.h>
#include <dlfcn.h>
#include <link.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "dualgraph/solvers/block/block_kernels_avx2.h"

#ifdef DUALGRAPH_BENCH_HAVE_CERES
#include <ceres/version.h>
#endif

namespace {

// Loaded shared objects whose file name mentions a BLAS or LAPACK.
int collectBlas(struct dl_phdr_info* info, size_t /*size*/, void* out) {
  const std::string name = info->dlpi_name != nullptr ? info->dlpi_name : "";
  if (name.find("blas") != std::string::npos || name.find("atlas") != std::string::npos ||
      name.find("lapack") != std::string::npos) {
    std::string& list = *static_cast<std::string*>(out);
    list += (list.empty() ? "" : ", ") + name;
  }
  return 0;
}

std::string blasDescription() {
  std::string libraries;
  dl_iterate_phdr(collectBlas, &libraries);
  // OpenBLAS names its build (core, threads) through openblas_get_config.
  using ConfigFn = char* (*)();
  if (auto config = reinterpret_cast<ConfigFn>(dlsym(RTLD_DEFAULT, "openblas_get_config"))) {
    libraries += std::string(" [") + config() + "]";
  }
  return libraries.empty() ? "none loaded" : libraries;
}

}  // namespace

int main(int argc, char** argv) {
#ifdef DUALGRAPH_BENCH_HAVE_CERES
  const std::string ceres = std::string("Ceres ") + CERES_VERSION_STRING + " (SPARSE_NORMAL_CHOLESKY, SuiteSparse)";
#else
  const std::string ceres = "Ceres: not found (built without the Ceres peer)";
#endif
#ifdef NDEBUG
  const std::string build = "release (NDEBUG)";
#else
  const std::string build = "WITHOUT NDEBUG: numbers are not representative";
#endif
  const std::string blas = blasDescription();
  const std::string kernels = dualgraph::block_kernels_avx2::enabled() ? "AVX2 + FMA (chosen at run time)"
                                                                        : "baseline SSE2 (this CPU has no AVX2 + FMA)";
  std::printf("dualgraph benchmarks: build %s\npeers: %s\nBLAS: %s\n6x6 block kernels: %s\n", build.c_str(), ceres.c_str(),
              blas.c_str(), kernels.c_str());
  std::fflush(stdout);
  benchmark::AddCustomContext("dualgraph_build", build);
  benchmark::AddCustomContext("peer_ceres", ceres);
  benchmark::AddCustomContext("blas", blas);
  benchmark::AddCustomContext("block_kernels", kernels);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
