#pragma once
// The progress line of `kdem run`: step, simulated time, rate and estimated time to finish.
// On a terminal it is one line rewritten in place ('\r') at most every 0.5 s; when stderr is a
// file or a pipe, one line is appended every 10 s. Nothing is printed when quiet.
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

namespace kdem {

class ProgressLine {
public:
  using Clock = std::chrono::steady_clock;

  // Prints to stderr, in place when stderr is a terminal.
  ProgressLine(bool quiet, std::int64_t total_steps);
  // Prints to stream; is_terminal chooses in-place updates every 0.5 s or lines every 10 s.
  ProgressLine(bool quiet, std::int64_t total_steps, std::FILE* stream, bool is_terminal);

  void update(std::int64_t step, double sim_time, double particle_steps_per_second);
  // Prints the last state once more (if not already shown) and ends the line.
  void finish();

private:
  void print(Clock::time_point now);
  double eta_seconds(Clock::time_point now) const;

  bool quiet_;
  std::int64_t total_steps_;
  std::FILE* stream_;
  bool is_terminal_;
  Clock::duration print_interval_;

  bool started_ = false;
  Clock::time_point first_update_time_;
  std::int64_t first_update_step_ = 0;
  Clock::time_point last_print_time_;
  bool last_state_shown_ = true;
  std::size_t last_line_length_ = 0;
  bool finished_ = false;

  std::int64_t step_ = 0;
  double sim_time_ = 0;
  double particle_steps_per_second_ = 0;
};

// "1:02:03" for 3723 s, "0:05" for 5 s, "--" when unknown (negative or not finite).
std::string format_duration(double seconds);

// The text of one progress line, e.g.
// "step 1200/10000 (12.0%)  t = 0.0012 s  3.45e+06 particle-steps/s  ETA 1:05".
// total_steps <= 0 leaves out the total, the percentage and the ETA.
std::string format_progress(std::int64_t step, std::int64_t total_steps, double sim_time,
                            double particle_steps_per_second, double eta_seconds);

} // namespace kdem
