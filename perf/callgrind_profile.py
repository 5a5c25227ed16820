"""Reads a callgrind profile (--dump-instr=yes) into per-function costs and calls, counts the
floating-point operations of the executed instructions from their disassembly, and splits the
cost of a root function into stages by the functions its call tree passes through.

Used by perf/callgrind_stages.py (instruction baseline, `make perf-check`) and by the GPU
performance model (perf/gpu_model.py), which takes the operation counts from here.
"""

import re
import subprocess
from collections import defaultdict

# FP64 operations per executed instruction (scalar sd: 1, packed pd: 2, 4 or 8 for 128-, 256-
# and 512-bit registers, fused multiply-add counts two). Compares, moves, logic (abs, negation)
# and conversions are not arithmetic and count zero, as in the usual flop conventions.
_FP_ARITHMETIC = ("add", "sub", "mul", "div", "sqrt", "min", "max")


def fp64_operations(mnemonic, packed_lanes=2):
    """packed_lanes: doubles in the instruction's register (2 xmm, 4 ymm, 8 zmm)."""
    m = mnemonic.lower()
    if m.startswith("v"):
        m = m[1:]
    fused = re.match(r"f(n?)m(add|sub)(sub|add)?(132|213|231)(sd|pd)$", m)
    if fused:
        return 2 if fused.group(5) == "sd" else 2 * packed_lanes
    for op in _FP_ARITHMETIC:
        if m == op + "sd":
            return 1
        if m == op + "pd":
            return packed_lanes
    return 0


def packed_lanes_of(operands):
    """Doubles per register of an instruction from its operand text (objdump syntax)."""
    if "%zmm" in operands:
        return 8
    if "%ymm" in operands:
        return 4
    return 2


class Disassembly:
    """Mnemonic at each instruction address of an object file (addresses as callgrind reports
    them: the file's virtual addresses, also for shared libraries), with the doubles per register
    of its operands (packed_lanes_of)."""

    def __init__(self):
        self._objects = {}

    def mnemonics(self, path):
        if path not in self._objects:
            table = {}
            try:
                text = subprocess.run(["objdump", "-d", "--no-show-raw-insn", path],
                                      capture_output=True, text=True, check=True).stdout
            except (OSError, subprocess.CalledProcessError):
                text = ""
            line = re.compile(r"^\s*([0-9a-f]+):\s+(?:\S+ )?\s*([a-z][a-z0-9.]*)(.*)$")
            for row in text.splitlines():
                found = line.match(row)
                if found:
                    table[int(found.group(1), 16)] = (found.group(2),
                                                       packed_lanes_of(found.group(3)))
            self._objects[path] = table
        return self._objects[path]


class Profile:
    """Self cost (Ir) per function and per (object, address), and the calls between functions
    with their inclusive cost, from one callgrind output file."""

    def __init__(self, path):
        self.self_ir = defaultdict(int)
        self.self_by_address = defaultdict(lambda: defaultdict(int))  # fn -> (obj, addr) -> Ir
        self.calls = defaultdict(lambda: defaultdict(int))  # caller -> callee -> inclusive Ir
        self.object_of = {}
        self.total_ir = 0
        self._read(path)

    def _read(self, path):
        names = {"fn": {}, "ob": {}}
        positions = ["line"]
        fn = ob = call_target = None
        call_object = None
        last = []
        pending_call = False

        def resolve(kind, value):
            found = re.match(r"\((\d+)\)(?:\s+(.*))?$", value)
            if not found:
                return value
            key, name = found.group(1), found.group(2)
            if name is not None:
                names[kind][key] = name
            return names[kind].get(key, value)

        def parse_positions(fields):
            values = []
            for k, field in enumerate(fields):
                previous = last[k] if k < len(last) else 0
                if field == "*":
                    values.append(previous)
                elif field[0] in "+-":
                    values.append(previous + int(field, 0))
                else:
                    values.append(int(field, 0))
            return values

        with open(path) as stream:
            for raw in stream:
                row = raw.rstrip("\n")
                if not row or row.startswith("#"):
                    continue
                if row.startswith("positions:"):
                    positions = row.split()[1:]
                    continue
                if row.startswith("summary:") or row.startswith("totals:"):
                    self.total_ir = int(row.split()[1])
                    continue
                key, sep, value = row.partition("=")
                if sep and key in ("fn", "cfn", "ob", "cob", "fl", "fi", "fe", "cfi", "cfl"):
                    if key == "fn":
                        fn = resolve("fn", value)
                        self.object_of.setdefault(fn, ob)
                    elif key == "cfn":
                        call_target = resolve("fn", value)
                    elif key == "ob":
                        ob = resolve("ob", value)
                        call_object = None
                    elif key == "cob":
                        call_object = resolve("ob", value)
                    continue
                if sep and key == "calls":
                    pending_call = True
                    continue
                if sep:
                    continue
                fields = row.split()
                if not fields or not (fields[0][0] in "0123456789+-*"):
                    continue
                count = len(positions)
                where = parse_positions(fields[:count])
                last = where
                cost = int(fields[count]) if len(fields) > count else 0
                if pending_call:
                    self.calls[fn][call_target] += cost
                    if call_target not in self.object_of and call_object:
                        self.object_of[call_target] = call_object
                    pending_call = False
                    call_object = None
                else:
                    self.self_ir[fn] += cost
                    address = where[positions.index("instr")] if "instr" in positions else None
                    if address is not None:
                        self.self_by_address[fn][(ob, address)] += cost

    def inclusive_ir(self, fn):
        return self.self_ir.get(fn, 0) + sum(self.calls.get(fn, {}).values())

    def self_fp64(self, fn, disassembly):
        """FP64 operations executed in fn itself (each instruction's count of executions is its
        Ir, one per execution)."""
        total = 0
        for (obj, address), executions in self.self_by_address.get(fn, {}).items():
            if obj is None:
                continue
            instruction = disassembly.mnemonics(obj).get(address)
            if instruction:
                mnemonic, packed_lanes = instruction
                total += executions * fp64_operations(mnemonic, packed_lanes)
        return total


def stage_costs(profile, root, stage_of, disassembly):
    """Ir and FP64 operations of `root` (inclusive), split by stage: a function's own cost goes to
    the stage of its nearest ancestor (itself included) that stage_of(name) names; calls are
    followed in proportion of their inclusive cost to the callee's (a callee's cost is taken as
    independent of its caller). Cost outside any named stage goes to 'other'."""
    result = defaultdict(lambda: {"instructions": 0.0, "fp64": 0.0})
    fp_cache = {}

    def self_fp(fn):
        if fn not in fp_cache:
            fp_cache[fn] = profile.self_fp64(fn, disassembly)
        return fp_cache[fn]

    def visit(fn, weight, stage, depth, path):
        own = stage_of(fn) or stage
        result[own]["instructions"] += weight * profile.self_ir.get(fn, 0)
        result[own]["fp64"] += weight * self_fp(fn)
        if depth > 200:
            return
        for callee, cost in profile.calls.get(fn, {}).items():
            callee_total = profile.inclusive_ir(callee)
            if callee in path or callee_total <= 0 or cost <= 0 or weight * cost < 1:
                continue
            visit(callee, weight * cost / callee_total, own, depth + 1, path | {callee})

    visit(root, 1.0, "other", 0, {root})
    return dict(result)


def find_function(profile, pattern):
    """The function whose name matches the regular expression, with the largest inclusive cost."""
    matches = [fn for fn in profile.self_ir.keys() | profile.calls.keys()
               if fn and re.search(pattern, fn)]
    if not matches:
        raise LookupError(f"no function matches {pattern!r} in the profile")
    return max(matches, key=profile.inclusive_ir)
