#include "progress.hpp"

#include <cmath>

#include <unistd.h>

namespace kdem {

namespace {

constexpr std::chrono::milliseconds terminal_interval{500};
constexpr std::chrono::seconds log_interval{10};

std::string printf_text(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

} // namespace

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) {
    return "--";
  }
  const auto whole_seconds = static_cast<long long>(std::llround(seconds));
  const long long hours = whole_seconds / 3600;
  const long long minutes = whole_seconds / 60 % 60;
  const long long remaining_seconds = whole_seconds % 60;
  char buffer[64];
  if (hours > 0) {
    std::snprintf(buffer, sizeof buffer, "%lld:%02lld:%02lld", hours, minutes, remaining_seconds);
  } else {
    std::snprintf(buffer, sizeof buffer, "%lld:%02lld", minutes, remaining_seconds);
  }
  return buffer;
}

std::string format_progress(std::int64_t step, std::int64_t total_steps, double sim_time,
                            double particle_steps_per_second, double eta_seconds) {
  std::string line = "step " + std::to_string(step);
  if (total_steps > 0) {
    line += "/" + std::to_string(total_steps) + " (" +
            printf_text("%.1f", 100.0 * static_cast<double>(step) / total_steps) + "%)";
  }
  line += "  t = " + printf_text("%.6g", sim_time) + " s  " +
          printf_text("%.3g", particle_steps_per_second) + " particle-steps/s";
  if (total_steps > 0) {
    line += "  ETA " + format_duration(eta_seconds);
  }
  return line;
}

ProgressLine::ProgressLine(bool quiet, std::int64_t total_steps)
    : ProgressLine(quiet, total_steps, stderr, ::isatty(::fileno(stderr)) != 0) {}

ProgressLine::ProgressLine(bool quiet, std::int64_t total_steps, std::FILE* stream,
                           bool is_terminal)
    : quiet_(quiet), total_steps_(total_steps), stream_(stream), is_terminal_(is_terminal),
      print_interval_(is_terminal ? Clock::duration(terminal_interval)
                                  : Clock::duration(log_interval)) {}

void ProgressLine::update(std::int64_t step, double sim_time, double particle_steps_per_second) {
  if (quiet_ || finished_) {
    return;
  }
  const Clock::time_point now = Clock::now();
  step_ = step;
  sim_time_ = sim_time;
  particle_steps_per_second_ = particle_steps_per_second;
  last_state_shown_ = false;
  if (!started_) {
    started_ = true;
    first_update_time_ = now;
    first_update_step_ = step;
    print(now);
  } else if (now - last_print_time_ >= print_interval_) {
    print(now);
  }
}

void ProgressLine::finish() {
  if (quiet_ || finished_) {
    return;
  }
  finished_ = true;
  if (!started_) {
    return;
  }
  if (!last_state_shown_) {
    print(Clock::now());
  }
  if (is_terminal_) {
    std::fputc('\n', stream_);
    std::fflush(stream_);
  }
}

// Remaining steps at the mean step rate since the first update (which may be a restart step).
double ProgressLine::eta_seconds(Clock::time_point now) const {
  const double elapsed = std::chrono::duration<double>(now - first_update_time_).count();
  const auto steps_done = static_cast<double>(step_ - first_update_step_);
  if (steps_done <= 0 || elapsed <= 0) {
    return -1;
  }
  return static_cast<double>(total_steps_ - step_) * elapsed / steps_done;
}

void ProgressLine::print(Clock::time_point now) {
  const std::string line =
      format_progress(step_, total_steps_, sim_time_, particle_steps_per_second_, eta_seconds(now));
  if (is_terminal_) {
    // Blank out what is left of a longer previous line.
    const std::size_t padding =
        last_line_length_ > line.size() ? last_line_length_ - line.size() : 0;
    std::fprintf(stream_, "\r%s%s", line.c_str(), std::string(padding, ' ').c_str());
  } else {
    std::fprintf(stream_, "%s\n", line.c_str());
  }
  std::fflush(stream_);
  last_line_length_ = line.size();
  last_print_time_ = now;
  last_state_shown_ = true;
}

} // namespace kdem
