#include "progress_bar.hpp"

#include <unistd.h>

#include <cstdio>

namespace granular::cli {

ProgressBar::ProgressBar(std::string label, std::uint64_t total, bool enabled)
    : label_(std::move(label)), total_(total == 0 ? 1 : total), enabled_(enabled), terminal_(::isatty(2) != 0),
      start_(std::chrono::steady_clock::now()), last_draw_(start_) {}

void ProgressBar::update(std::uint64_t done) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (terminal_) {
    if (now - last_draw_ < std::chrono::milliseconds(100) && done < total_) return;
    last_draw_ = now;
    draw(done);
  } else {
    const int decile = int(done * 10 / total_);
    if (decile == last_decile_) return;
    last_decile_ = decile;
    draw(done);
  }
}

void ProgressBar::finish() {
  if (!enabled_) return;
  if (!terminal_ && last_decile_ == 10) return;
  draw(total_);
  if (terminal_) std::fputc('\n', stderr);
}

void ProgressBar::draw(std::uint64_t done) {
  constexpr int kWidth = 40;
  const double fraction = double(done) / double(total_);
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::string bar(kWidth, ' ');
  for (int i = 0; i < int(fraction * kWidth); ++i) bar[std::size_t(i)] = '#';
  std::fprintf(stderr, "%s%s [%s] %3d%%  %llu/%llu  %.1fs%s", terminal_ ? "\r" : "", label_.c_str(), bar.c_str(),
               int(fraction * 100), static_cast<unsigned long long>(done), static_cast<unsigned long long>(total_),
               elapsed, terminal_ ? "" : "\n");
  std::fflush(stderr);
}

}  // namespace granular::cli
