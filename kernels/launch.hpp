#pragma once
// How a heavy kernel is laid out on the hardware: a flat range of items (Kokkos picks the GPU
// block size), or teams of `team_size` lanes, one item per lane (team_size is then the CUDA
// block size: fewer lanes per block leave more registers per lane to a register-heavy kernel
// such as an iterative narrow phase). On CPU backends a team is a group of threads; the
// size is clamped to what the backend allows.
#include "types.hpp"

namespace kdem {

// Reduces body(item, tally) over items [0, count) into `reducer`, laid out as team_size asks
// (0: a flat range).
template <class Tally, class Reducer, class Body>
void reduce_over_items(const std::string& label, int count, int team_size, const Body& body,
                       const Reducer& reducer) {
  if (team_size <= 0) {
    Kokkos::parallel_reduce(label, RangePolicy(0, count), body, reducer);
    return;
  }
  using Team = Kokkos::TeamPolicy<ExecSpace>;
  using Member = typename Team::member_type;
  const auto team_body = KOKKOS_LAMBDA(const Member& team, Tally& tally) {
    const int lanes = team.team_size();
    const int first = team.league_rank() * lanes;
    Tally part;
    Kokkos::parallel_reduce(
        Kokkos::TeamThreadRange(team, lanes),
        [&](int lane, Tally& lane_tally) {
          if (first + lane < count)
            body(first + lane, lane_tally);
        },
        Kokkos::Sum<Tally>(part));
    Kokkos::single(Kokkos::PerTeam(team), [&]() { tally += part; });
  };
  const int allowed = Team(1, Kokkos::AUTO).team_size_max(team_body, Kokkos::ParallelReduceTag());
  const int lanes = team_size < allowed ? team_size : allowed;
  const int league = count > 0 ? (count + lanes - 1) / lanes : 0;
  Kokkos::parallel_reduce(label, Team(league, lanes), team_body, reducer);
}

} // namespace kdem
