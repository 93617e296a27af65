#include "lut_command.hpp"

#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "choices_text.hpp"
#include "json_text.hpp"
#include "granular/extend/hex.hpp"
#include "granular/extend/lut.hpp"
#include "granular/rule_presets.hpp"
#include "granular/world_def.hpp"
#include "number_option.hpp"
#include "output_paths.hpp"

namespace granular::cli {

namespace {

struct LutOptions {
  std::string rules = WorldDef{}.rules;
  std::string cache_dir;
  bool rebuild = false;
  int threads = 0;
  bool json = false;
};

void run(const LutOptions& o) {
  const auto rules = make_rule_set(o.rules);
  LutCacheOptions cache;
  cache.directory = o.cache_dir;
  cache.threads = o.threads;
  double build_seconds = -1;
  if (o.rebuild) {
    // Always build (and validate) once, timed on its own, then refresh the cache.
    const auto start = std::chrono::steady_clock::now();
    const Lut built = Lut::build(*rules, o.threads);
    build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const auto dir = o.cache_dir.empty() ? default_lut_cache_dir() : std::filesystem::path(o.cache_dir);
    if (!dir.empty()) std::filesystem::remove(lut_cache_file(*rules, dir));
  }
  const LutObtained got = obtain_lut(*rules, cache);
  if (!got.notice.empty()) std::fprintf(stderr, "notice: %s\n", got.notice.c_str());
  const Lut& lut = *got.lut;
  const std::uint64_t cache_bytes =
      got.cache_file.empty() || !std::filesystem::exists(got.cache_file) ? 0 : std::filesystem::file_size(got.cache_file);
  nlohmann::json j;
  j["rules"] = rules->name;
  j["description"] = rules->description;
  j["entries"] = lut.entries().size();
  j["bytes"] = lut.size_bytes();
  j["moving_keys"] = lut.moving_keys();
  j["content_hash"] = hex64(lut.content_hash());
  j["rule_fingerprint"] = hex64(lut.rule_fingerprint());
  j["validated"] = true;
  j["source"] = got.from_cache ? "cache" : "built";
  j["seconds"] = got.seconds;
  if (build_seconds >= 0) j["build_seconds"] = build_seconds;
  j["cache_file"] = got.cache_file.string();
  j["cache_bytes"] = cache_bytes;
  if (o.json) {
    std::cout << json_text(j);
    return;
  }
  std::printf("rules          %s: %s\n", rules->name.c_str(), rules->description.c_str());
  std::printf("entries        %zu (%.1f MiB), %llu keys move cells\n", lut.entries().size(),
              double(lut.size_bytes()) / (1024.0 * 1024.0), static_cast<unsigned long long>(lut.moving_keys()));
  std::printf("validated      every entry is a permutation; solid never moves\n");
  if (build_seconds >= 0) std::printf("build          %.3f s (build + validate)\n", build_seconds);
  std::printf("%-14s %.3f s\n", got.from_cache ? "cache load" : "build", got.seconds);
  std::printf("content hash   %s\n", hex64(lut.content_hash()).c_str());
  std::printf("fingerprint    %s\n", hex64(lut.rule_fingerprint()).c_str());
  if (got.cache_file.empty())
    std::printf("cache          disabled\n");
  else
    std::printf("cache          %s (%.2f MiB)\n", got.cache_file.c_str(), double(cache_bytes) / (1024.0 * 1024.0));
}

}  // namespace

void add_lut_command(CLI::App& app) {
  auto options = std::make_shared<LutOptions>();
  CLI::App* cmd = app.add_subcommand("lut", "build, validate and cache a rule set's transition table");
  cmd->add_option("--rules", options->rules, "rule set: " + rule_preset_choices())->capture_default_str();
  cmd->add_option("--cache-dir", options->cache_dir, "cache folder (default: $GRANULAR_CACHE_DIR or ~/.cache/granular)")
      ->check(non_empty_path());
  cmd->add_flag("--rebuild", options->rebuild, "build even when cached, and time the build");
  add_number_option(*cmd, "-j,--threads", options->threads, threads_range(),
                    "threads for the build (0 = all)");
  cmd->add_flag("--json", options->json, "print as JSON");
  cmd->callback([options] { run(*options); });
}

}  // namespace granular::cli
