/// @file bench_cuda_step.cu
/// GPU step throughput on the paper's bowl scene, dense stepping, in one process:
///   (1) paper     the paper's layout: one int32 per cell, the full 8^8 uint32 permutation table in
///                 global memory, one CUDA block of 256 threads per horizontal layer of blocks
///                 (interior blocks only, as in the paper), gather-key-lookup-permute-scatter;
///   (2) backend   the CUDA backend's own dense kernel (block_walk.cuh): a byte per cell and the
///                 result table, one thread per 4 blocks; also with the isotropic rule's random
///                 symmetry; and its fused two-tick kernel (pair_kernel.cuh), one launch per
///                 even-odd pair of ticks, right after the release and mid-fall;
///   (3) memcpy    a device-to-device copy of the grid's bytes: the bandwidth ceiling (a copy reads
///                 and writes one byte per cell, the least any step can move).
/// Prints cell-updates per second and ratios, and writes bench_cuda.csv.
///
///   bench_cuda_step [output-dir]      (default: $OUT when set, else the current directory)
///   environment: GRANULAR_BENCH_SIZES="256,512,1024,2048"  GRANULAR_BENCH_TICKS=64
///                GRANULAR_BENCH_PAIR_CHUNKS="16,32,64" (extra pair rows with fixed chunk heights)

#include <cuda_runtime.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "cuda_check.cuh"
#include "cuda_device.cuh"
#include "cuda_stream.cuh"
#include "device_buffer.cuh"
#include "granular/extend/block.hpp"
#include "granular/errors.hpp"
#include "granular/scene.hpp"
#include "reduce_kernels.cuh"
#include "block_walk.cuh"
#include "granular/rule_presets.hpp"
#include "pair_kernel.cuh"
#include "rule_launch.cuh"
#include "step/block_step.hpp"
#include "step/step_materials.hpp"
#include "table_kernels.cuh"

namespace {

using namespace granular;

/// Threads per CUDA block of the paper's kernel.
constexpr int kPaperThreads = 256;

/// One tick in the paper's layout: CUDA block b takes block layer b (z0 = 2b - offset.z); its
/// threads stride over the layer's interior blocks; edge blocks are left alone, as in the paper.
__global__ void __launch_bounds__(kPaperThreads) paper_step_kernel(int* cells, Int3 size, const Transition* lut,
                                                                    std::uint64_t tick) {
  const BlockOffset o = block_offset(tick);
  const int z0 = 2 * int(blockIdx.x) - o.z;
  if (z0 < 0 || z0 + 1 >= size.z) return;
  const int xs = o.x, ys = o.y;  // first interior block corner along x and y
  const int nbx = (size.x - xs) / 2, nby = (size.y - ys) / 2;
  const std::int64_t sy = size.x, sz = sy * size.y;
  for (int b = int(threadIdx.x); b < nbx * nby; b += kPaperThreads) {
    const int x0 = xs + 2 * (b % nbx), y0 = ys + 2 * (b / nbx);
    int* const base = cells + x0 + sy * y0 + sz * z0;
    std::int64_t at[8];
    int cell[8];
    BlockKey key = 0;
#pragma unroll
    for (int i = 0; i < 8; ++i) {
      at[i] = std::int64_t(i & 1) + sy * ((i >> 1) & 1) + sz * (i >> 2);
      cell[i] = base[at[i]];
      key |= BlockKey(cell[i]) << (3 * i);
    }
    const Transition t = lut[key];
#pragma unroll
    for (int i = 0; i < 8; ++i) base[at[destination(t, i)]] = cell[i];
  }
}

/// Widens byte cells to int32 cells.
__global__ void widen_kernel(const std::uint8_t* in, int* out, std::uint64_t n) {
  for (std::uint64_t i = std::uint64_t(blockIdx.x) * blockDim.x + threadIdx.x; i < n;
       i += std::uint64_t(gridDim.x) * blockDim.x)
    out[i] = in[i];
}

/// One measured variant at one N.
struct Row {
  int n = 0;
  std::uint64_t cells = 0;
  std::string variant;
  double seconds_per_tick = 0;
  double bytes_per_cell = 0;
  double updates_per_s() const { return double(cells) / seconds_per_tick; }
};

int env_int(const char* name, int fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::atoi(v) : fallback;
}

std::vector<int> bench_sizes() {
  const char* v = std::getenv("GRANULAR_BENCH_SIZES");
  std::vector<int> sizes;
  std::stringstream s(v && *v ? v : "256,512,1024,2048");
  for (std::string item; std::getline(s, item, ',');)
    if (!item.empty()) sizes.push_back(std::atoi(item.c_str()));
  return sizes;
}

/// Fixed chunk heights of the pair kernel to measure besides the backend's own choice.
std::vector<int> pair_chunks() {
  const char* v = std::getenv("GRANULAR_BENCH_PAIR_CHUNKS");
  std::vector<int> chunks;
  std::stringstream s(v && *v ? v : "");
  for (std::string item; std::getline(s, item, ',');)
    if (!item.empty()) chunks.push_back(std::atoi(item.c_str()));
  return chunks;
}

std::size_t free_device_bytes() {
  std::size_t free_bytes = 0, total = 0;
  cuda::check(cudaMemGetInfo(&free_bytes, &total), "cudaMemGetInfo");
  return free_bytes;
}

/// Runs `warmup` then `ticks` calls of tick(t) (t counting from 0) and returns seconds per call.
template <class Tick>
double time_ticks(cuda::Stream& stream, int warmup, int ticks, Tick&& tick) {
  for (int t = 0; t < warmup; ++t) tick(std::uint64_t(t));
  stream.synchronize("warm-up");
  cuda::Event start, stop;
  start.record(stream.get());
  for (int t = warmup; t < warmup + ticks; ++t) tick(std::uint64_t(t));
  stop.record(stream.get());
  return double(stop.ms_since(start)) / 1000.0 / ticks;
}

/// Cells per material on the device, for the mass check.
std::vector<unsigned long long> device_counts(const std::uint8_t* cells, std::uint64_t n, int sm_count,
                                              cuda::Stream& stream) {
  cuda::DeviceBuffer<unsigned long long> counts(kMaterialCount, "counters");
  cuda::check(cudaMemsetAsync(counts.data(), 0, counts.bytes(), stream.get()), "cudaMemsetAsync");
  cuda::count_kernel<<<cuda::reduce_blocks(n, sm_count), cuda::kReduceThreads, 0, stream.get()>>>(cells, n, counts.data());
  cuda::check_launch("count kernel");
  std::vector<unsigned long long> host(kMaterialCount);
  cuda::check(cudaMemcpyAsync(host.data(), counts.data(), counts.bytes(), cudaMemcpyDeviceToHost, stream.get()),
              "cudaMemcpyAsync");
  stream.synchronize("count");
  return host;
}

std::filesystem::path output_dir(int argc, char** argv) {
  if (argc > 1) return argv[1];
  const char* out = std::getenv("OUT");
  if (out && *out) return out;
  return std::filesystem::current_path();
}

/// The backend's kernels on a grid of the bench: one tick, or an even-odd pair of ticks, of the
/// one-step rules (the paper's table, with or without random symmetry).
struct BenchStepper {
  cuda::DeviceCells grid;  ///< the cells
  StepRules rules;         ///< the tables and flags

  /// Enqueues tick `tick` with the dense kernel (the backend's own, from granular_cuda).
  void step(std::uint64_t tick, const cuda::StepShape& shape, cudaStream_t stream) const {
    cuda::with_device_step(rules, tick, [&](const auto& rule) {
      cuda::RuleLaunch<std::decay_t<decltype(rule)>>::dense(grid, rule, shape, nullptr, stream);
    });
  }
  /// Enqueues ticks `tick` (even) and `tick + 1` with the pair kernel (the backend's own).
  void pair(std::uint64_t tick, const cuda::PairShape& shape, std::uint8_t* halo, cudaStream_t stream) const {
    cuda::with_device_step_pair(rules, tick, [&](const auto& a, const auto& b) {
      cuda::RuleLaunch<std::decay_t<decltype(a)>>::pair(grid, a, b, shape, halo, nullptr, stream);
    });
  }
};

int run(int argc, char** argv) {
  const std::filesystem::path out_dir = output_dir(argc, argv);
  std::filesystem::create_directories(out_dir);
  const int ticks = env_int("GRANULAR_BENCH_TICKS", 64), warmup = 8;
  const cuda::DeviceInfo device = cuda::acquire_device();
  std::printf("device: %s, %d SMs; %d timed ticks after %d warm-up ticks per variant\n", cuda::describe(device).c_str(),
              device.sm_count, ticks, warmup);

  cuda::Stream stream;
  const std::size_t table_bytes = std::size_t(kBlockKeyCount) * sizeof(Transition);
  cuda::DeviceBuffer<Transition> lut(kBlockKeyCount, "the transition table");
  cuda::DeviceBuffer<BlockKey> result(kBlockKeyCount, "the result table");
  const StepMaterials materials = step_materials(default_materials());
  cuda::launch_paper_lut(lut.data(), materials, stream.get());
  cuda::launch_result_table(lut.data(), result.data(), stream.get());
  stream.synchronize("building the tables");

  const Scene scene = load_scene(find_scene("bowl"));
  std::vector<Row> rows;
  for (const int n : bench_sizes()) {
    const Int3 size = scene_size(scene, n);
    const std::uint64_t cells = std::uint64_t(size.x) * std::uint64_t(size.y) * std::uint64_t(size.z);
    if (cuda::cell_buffer_bytes(cells) > free_device_bytes()) {
      std::printf("N=%d: %s grid (%llu bytes) does not fit in device memory; skipped\n", n, to_string(size).c_str(),
                  (unsigned long long)cells);
      continue;
    }
    std::printf("N=%d: building the scene on the host...\n", n);
    std::fflush(stdout);
    const SceneInstance inst = instantiate(scene, n);
    cuda::DeviceBuffer<std::uint8_t> bytes(cuda::cell_buffer_bytes(cells), "the grid's cells");
    auto upload = [&] {
      cuda::check(cudaMemcpy(bytes.data(), inst.grid.cells().data(), cells, cudaMemcpyHostToDevice), "upload");
    };
    const unsigned fill_blocks = unsigned(device.sm_count) * 8;

    // (1) the paper's layout.
    if (std::uint64_t(cells) * 4 < free_device_bytes()) {
      upload();
      cuda::DeviceBuffer<int> wide(cells, "int32 cells");
      widen_kernel<<<fill_blocks, 256, 0, stream.get()>>>(bytes.data(), wide.data(), cells);
      cuda::check_launch("widen kernel");
      const unsigned layers = unsigned(block_count(size.z, 1));
      const double s = time_ticks(stream, warmup, ticks, [&](std::uint64_t t) {
        paper_step_kernel<<<layers, kPaperThreads, 0, stream.get()>>>(wide.data(), size, lut.data(), t);
      });
      cuda::check_launch("paper step kernel");
      rows.push_back({n, cells, "paper_int32_lut", s, (4.0 * double(cells) + double(table_bytes)) / double(cells)});
    } else {
      std::printf("N=%d: (1) the paper's int32 layout needs %.2f GB; it does not fit in device memory, skipped\n", n,
                  4.0 * double(cells) / 1e9);
    }

    // (2) this backend's kernel: both rule sets right after the release (most 32-cell groups
    // uniform), and the paper rule mid-fall (N/2 ticks in: the falling column is rarefied into
    // alternating layers, so most blocks are mixed: the worst case for the uniform-group skip).
    // The fused two-tick kernel (pair_kernel.cuh) runs the same states: one launch per 2
    // ticks, timed over the same number of ticks and reported per tick. chunk 0 is the backend's
    // own choice of chunk height; GRANULAR_BENCH_PAIR_CHUNKS="16,32,64" adds rows for fixed ones.
    struct Variant {
      bool random_symmetry;
      int start_tick;
      std::string name;
      bool pair = false;
      int chunk = 0;
    };
    std::vector<Variant> variants = {{false, 0, "backend_u8_paper"},
                                     {false, 0, "backend_u8_pair_paper", true},
                                     {true, 0, "backend_u8_isotropic"},
                                     {false, n / 2, "backend_u8_paper_midfall"},
                                     {false, n / 2, "backend_u8_pair_midfall", true}};
    for (const int chunk : pair_chunks())
      variants.push_back({false, n / 2, "backend_u8_pair_midfall_h" + std::to_string(chunk), true, chunk});
    for (const Variant& v : variants) {
      upload();
      const auto before = device_counts(bytes.data(), cells, device.sm_count, stream);
      BenchStepper p;
      p.grid = {bytes.data(), size};
      p.rules.result = result.data();
      p.rules.seed = 1;
      p.rules.random_symmetry = v.random_symmetry;
      p.rules.materials = materials;
      const cuda::StepShape shape = cuda::step_shape(size);
      const cuda::PairShape pair = cuda::pair_shape(size, v.chunk);
      const std::size_t halo_bytes = cuda::pair_halo_bytes(size, pair);
      std::optional<cuda::DeviceBuffer<std::uint8_t>> halo;
      if (v.pair && halo_bytes > 0) halo.emplace(halo_bytes, "the pair kernel's halo");
      for (int t = 0; t < v.start_tick; ++t) {
        p.step(std::uint64_t(t), shape, stream.get());
      }
      double s = 0;
      if (v.pair) {
        const int first = v.start_tick + v.start_tick % 2;  // pairs start at an even tick
        if (first != v.start_tick) {
          p.step(std::uint64_t(v.start_tick), shape, stream.get());
        }
        s = time_ticks(stream, warmup / 2, ticks / 2, [&](std::uint64_t t) {
              p.pair(std::uint64_t(first) + 2 * t, pair, halo ? halo->data() : nullptr, stream.get());
            }) / 2;
      } else {
        s = time_ticks(stream, warmup, ticks, [&](std::uint64_t t) {
          p.step(std::uint64_t(v.start_tick) + t, shape, stream.get());
        });
      }
      stream.synchronize("backend step");
      const auto after = device_counts(bytes.data(), cells, device.sm_count, stream);
      if (before != after)
        std::printf("N=%d: WARNING: %s did not conserve the materials\n", n, v.name.c_str());
      if (v.pair) std::printf("N=%d: %s: chunks of %d layers (%d along z)\n", n, v.name.c_str(), pair.chunk, pair.chunks);
      rows.push_back({n, cells, v.name, s, (double(cuda::cell_buffer_bytes(cells)) + double(table_bytes)) / double(cells)});
    }

    // The fused pair against two single ticks on the same state, cell for cell (mid-fall, both
    // rule sets): a mismatch is reported, never hidden in a throughput number.
    for (const bool random_symmetry : {false, true}) {
      if (n > 1024) break;  // the host comparison of a larger grid costs more than it tells
      cuda::DeviceBuffer<std::uint8_t> twin(cuda::cell_buffer_bytes(cells), "the pair check's twin grid");
      BenchStepper a;
      a.rules.result = result.data();
      a.rules.seed = 7;
      a.rules.random_symmetry = random_symmetry;
      a.rules.materials = materials;
      const cuda::StepShape shape = cuda::step_shape(size);
      const cuda::PairShape pair = cuda::pair_shape(size);
      const std::size_t halo_bytes = cuda::pair_halo_bytes(size, pair);
      std::optional<cuda::DeviceBuffer<std::uint8_t>> halo;
      if (halo_bytes > 0) halo.emplace(halo_bytes, "the pair kernel's halo");
      upload();
      a.grid = {bytes.data(), size};
      for (int t = 0; t < n / 2; ++t) a.step(std::uint64_t(t), shape, stream.get());
      cuda::check(cudaMemcpyAsync(twin.data(), bytes.data(), cells, cudaMemcpyDeviceToDevice, stream.get()), "copy");
      BenchStepper b = a;
      b.grid.cells = twin.data();
      for (int t = n / 2; t < n / 2 + 8; t += 2) {
        a.step(std::uint64_t(t), shape, stream.get());
        a.step(std::uint64_t(t + 1), shape, stream.get());
        b.pair(std::uint64_t(t), pair, halo ? halo->data() : nullptr, stream.get());
      }
      stream.synchronize("pair check");
      std::vector<std::uint8_t> single_host(cells), pair_host(cells);
      cuda::check(cudaMemcpy(single_host.data(), bytes.data(), cells, cudaMemcpyDeviceToHost), "download");
      cuda::check(cudaMemcpy(pair_host.data(), twin.data(), cells, cudaMemcpyDeviceToHost), "download");
      std::uint64_t differ = 0;
      for (std::uint64_t i = 0; i < cells; ++i) differ += single_host[i] != pair_host[i];
      std::printf("N=%d: pair kernel vs two single ticks (%s, 4 pairs from tick %d): %llu cells differ\n", n,
                  random_symmetry ? "isotropic" : "paper", n / 2, (unsigned long long)differ);
    }

    // (3) the bandwidth ceiling.
    if (cuda::cell_buffer_bytes(cells) < free_device_bytes()) {
      cuda::DeviceBuffer<std::uint8_t> copy(cuda::cell_buffer_bytes(cells), "the copy's target");
      const double s = time_ticks(stream, warmup, ticks, [&](std::uint64_t) {
        cuda::check(cudaMemcpyAsync(copy.data(), bytes.data(), cells, cudaMemcpyDeviceToDevice, stream.get()),
                    "cudaMemcpyAsync (device to device)");
      });
      rows.push_back({n, cells, "memcpy_d2d", s, 2.0});
    } else {
      std::printf("N=%d: no room for a second copy of the grid; (3) skipped\n", n);
    }
  }

  std::printf("\n%6s %14s %-30s %14s %16s %12s\n", "N", "cells", "variant", "ms/tick", "cell-updates/s", "bytes/cell");
  for (const Row& r : rows)
    std::printf("%6d %14llu %-30s %14.4f %16.4g %12.3f\n", r.n, (unsigned long long)r.cells, r.variant.c_str(),
                r.seconds_per_tick * 1e3, r.updates_per_s(), r.bytes_per_cell);
  std::printf("\n%6s %15s %15s %21s %21s %12s %22s %22s\n", "N", "backend/paper", "backend/memcpy",
              "isotropic/paper-rule", "midfall/paper-layout", "pair/single", "pair/single midfall",
              "pair midfall/memcpy");
  auto find = [&](int n, const char* variant) -> std::optional<Row> {
    for (const Row& r : rows)
      if (r.n == n && r.variant == variant) return r;
    return std::nullopt;
  };
  for (const int n : bench_sizes()) {
    const auto backend = find(n, "backend_u8_paper");
    if (!backend) continue;
    const auto paper = find(n, "paper_int32_lut"), copy = find(n, "memcpy_d2d"), iso = find(n, "backend_u8_isotropic"),
               midfall = find(n, "backend_u8_paper_midfall"), pair = find(n, "backend_u8_pair_paper"),
               pair_midfall = find(n, "backend_u8_pair_midfall");
    auto ratio = [&](const std::optional<Row>& a, const std::optional<Row>& b) {
      char text[32] = "n/a";
      if (a && b) std::snprintf(text, sizeof text, "%.3f", a->updates_per_s() / b->updates_per_s());
      return std::string(text);
    };
    std::printf("%6d %15s %15s %21s %21s %12s %22s %22s\n", n, ratio(backend, paper).c_str(),
                ratio(backend, copy).c_str(), ratio(iso, backend).c_str(), ratio(midfall, paper).c_str(),
                ratio(pair, backend).c_str(), ratio(pair_midfall, midfall).c_str(), ratio(pair_midfall, copy).c_str());
  }
  std::printf("(memcpy cells/s = bytes copied per second; a step reads every cell and writes only moved ones)\n");

  const std::filesystem::path csv = out_dir / "bench_cuda.csv";
  std::ofstream file(csv);
  file << "N,cells,variant,seconds_per_tick,cell_updates_per_s,bytes_per_cell\n";
  for (const Row& r : rows)
    file << r.n << ',' << r.cells << ',' << r.variant << ',' << r.seconds_per_tick << ',' << r.updates_per_s() << ','
         << r.bytes_per_cell << '\n';
  file.close();
  if (!file) throw FileError("could not write " + csv.string());
  std::printf("wrote %s\n", csv.string().c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_cuda_step: error: %s\n", e.what());
    return 1;
  }
}
