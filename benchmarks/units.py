"""Issue 31: what units cost. The n-link pendulum from particles (as benchmarks/cli.py
writes it) loaded with bare numbers and with units (m1 = "1 kg", l1 = "1 m",
g = "9.81 m/s^2"), and the dimension check alone (every term of every position, mass
and gravity, the coordinates' units inferred), in CPU seconds (medians).

    python benchmarks/units.py [--repeat 7] [--sizes 20,100]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
import tomllib
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

from cli import chain_model
from lagrangian.model.build import build_system
from lagrangian.model.dimension_check import Names, check_dimensions
from lagrangian.model.spec import expression_fields
from lagrangian.model.toml_io import loads, spec_from_mapping
from lagrangian.model.units import read_units
from lagrangian.parsing import syntax_tree


def with_units(text: str) -> str:
    """The chain's text with every parameter's value given with its unit."""
    lines = []
    for line in text.splitlines():
        name, _, value = line.partition(" = ")
        if name[:1] in "ml" and name[1:].isdigit():
            line = f'{name} = "{value} {"kg" if name[0] == "m" else "m"}"'
        elif name == "g" and value == "9.81":
            line = 'g = "9.81 m/s^2"'
        lines.append(line)
    return "\n".join(lines)


def cpu(function, repeat: int) -> float:
    """Median CPU seconds of ``function()``."""
    times = []
    for _ in range(repeat):
        start = time.process_time()
        function()
        times.append(time.process_time() - start)
    return statistics.median(times)


def check_only(text: str, *, parsed: bool):
    """The dimension check of ``text``'s model, ready to run (its System built before);
    ``parsed``: with the syntax trees the build keeps (as a load runs it), else parsing
    every text again."""
    spec, declared, _ = read_units(spec_from_mapping(tomllib.loads(text)))
    fields = [value for _, value, _ in expression_fields(spec) if isinstance(value, str)]
    trees = {value: syntax_tree(value) for value in fields} if parsed else None
    system = build_system(spec)
    names = Names(
        coordinates=system.coordinate_names,
        parameters=system.parameter_names,
        functions=(),
        known={name: unit.dimension for name, unit in declared.items()},
    )
    return lambda: check_dimensions(spec, names, trees)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--sizes", default="20,100")
    arguments = parser.parse_args()
    start = time.process_time()
    loads(with_units(chain_model(1)))  # pint's import and registry, once per process
    first = time.process_time() - start
    print(f"first model with units in a process (pint imported): {first:.3f} s CPU")
    print("links | load, no units | load, with units | ratio | check | check, parsing again")
    for n in (int(s) for s in arguments.sizes.split(",")):
        plain, dimensioned = chain_model(n), with_units(chain_model(n))
        assert loads(dimensioned).units is not None and loads(plain).units is None
        bare = cpu(lambda: loads(plain), arguments.repeat)  # noqa: B023
        units = cpu(lambda: loads(dimensioned), arguments.repeat)  # noqa: B023
        check = cpu(check_only(dimensioned, parsed=True), arguments.repeat)
        again = cpu(check_only(dimensioned, parsed=False), arguments.repeat)
        ratio = units / bare
        times = f"{check * 1000:.1f} ms | {again * 1000:.1f} ms"
        print(f"{n:5d} | {bare:.3f} s | {units:.3f} s | {ratio:.2f}x | {times}")


if __name__ == "__main__":
    main()
