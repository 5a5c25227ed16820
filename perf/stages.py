"""The stages of a kdem time step, as the performance tools split it: by the functions a call
tree passes through (callgrind) and by kernel label (Kokkos Tools, `kdem run --kernel-times`)."""

import re

# (stage, pattern of demangled function names that begin it); the first match names a
# function's stage, and functions without a match belong to the stage of their caller.
FUNCTION_STAGES = [
    ("integration", r"kdem::kick(_and_drift)?(_rigid)?[<(]"),
    ("binning", r"kdem::sort_particles_by_cell|kdem::make_cell_grid"),
    ("lists", r"kdem::Engine::State::rebuild_lists|kdem::build_pair_list|"
              r"kdem::transfer_pair_history|kdem::build_wall_contact_list|"
              r"kdem::transfer_wall_history|kdem::sort_into_families|"
              r"kdem::max_displacement_squared|kdem::Engine::State::lists_are_stale|"
              r"kdem::remember_build_positions|kdem::rows_by_id|kdem::rows_by_key|"
              r"kdem::present_families|kdem::Engine::State::classify_families"),
    ("walls", r"kdem::compute_\w*wall_contacts|kdem::update_wall_poses"),
    ("superquadric box tests", r"kdem::(implicit|superquadric)_pairs_in_reach"),
    ("superquadric narrow phase", r"kdem::superquadric_pair_contact|"
                                  r"kdem::sphere_superquadric_contact|kdem::narrow_phase::|"
                                  r"kdem::piecewise_pair_contact|"
                                  r"kdem::sphere_poly_superquadric_contact"),
    # Hertz-Mindlin with history, shared by every pair kernel
    ("contact law", r"kdem::PairSlots::(apply|clear)|kdem::hertz_mindlin"),
    # the rest of the superquadric pair kernels: warm starts, certificates, counters
    ("superquadric contacts", r"kdem::compute_pair_type<kdem::\w+, kdem::(Poly)?SuperquadricFamily|"
                              r"kdem::(Implicit|Superquadric|PolySuperquadric)PairState|"
                              r"kdem::NarrowPhase<kdem::\w+, kdem::(Poly)?SuperquadricFamily>"),
    # the sphere pair kernel is inlined into the function that calls the pair kernels
    ("sphere contacts", r"kdem::compute_pair_type<kdem::SphereFamily, kdem::SphereFamily|"
                        r"kdem::NarrowPhase<kdem::SphereFamily, kdem::SphereFamily>|"
                        r"kdem::Engine::State::compute_forces_of_families"),
    # gravity, wall and pair contributions summed per particle
    ("gather", r"kdem::sum_forces"),
    ("outlets", r"kdem::Engine::State::remove_discharged_particles"),
    ("insertion", r"kdem::Engine::State::insert_due_particles"),
]

# (stage, pattern of kernel labels); the first match wins.
KERNEL_STAGES = [
    ("integration", r"^kdem::kick(_and_drift)?$"),
    ("binning", r"^kdem::(bin_count|bin_fill|bin_order_by_id|gather_rows)$"),
    ("lists", r"^kdem::(max_displacement|pair_count|pair_fill|pair_reverse_\w+|"
              r"pair_history_transfer|rows_by_id|wall_candidate_\w+|wall_history_transfer|"
              r"flag_rows|kept_indices|exclusive_scan|narrow_phase_state_transfer|"
              r"rows_by_key|rows_by_key_fill|present_families)$"),
    ("walls", r"^kdem::(\w+_wall_contacts|wall_poses)$"),
    ("superquadric box tests", r"^kdem::(poly_)?superquadric_pair_(prefilter|compact)$"),
    ("superquadric contacts", r"^kdem::(superquadric_pair_forces|sphere_superquadric_forces|"
                              r"\w*poly_superquadric_forces)$"),
    ("sphere contacts", r"^kdem::sphere_pair_forces$"),
    ("gather", r"^kdem::sum_forces$"),
    ("outlets", r"^kdem::outlets$"),
    ("output", r"^kdem::(energy|pair_contact_statistics|wall_contact_statistics)$"),
    ("allocation", r"^Kokkos::"),
]

_FUNCTIONS = [(name, re.compile(p)) for name, p in FUNCTION_STAGES]
_KERNELS = [(name, re.compile(p)) for name, p in KERNEL_STAGES]


def stage_of_function(name):
    for stage, pattern in _FUNCTIONS:
        if pattern.search(name):
            return stage
    return None


def stage_of_kernel(label):
    for stage, pattern in _KERNELS:
        if pattern.search(label):
            return stage
    return "other"


def kernel_stages(kernel_times):
    """{stage: {"seconds", "launches"}} from a kernel_times.json document."""
    stages = {}
    for label, tally in kernel_times["kernels"].items():
        s = stages.setdefault(stage_of_kernel(label), {"seconds": 0.0, "launches": 0})
        s["seconds"] += tally["seconds"]
        s["launches"] += tally["launches"]
    return stages
