#!/usr/bin/env python3
"""Compare the RIHS01 type hashes of the interface packages under interfaces/ with a reference.

Why this exists: a ROS 2 Jazzy peer (a Nav2 client, a SMACC2 tool, a bag recorder) only matches
our topics, services and actions when every type hash is identical, and a CMake build of all
five packages takes minutes. This tool needs no CMake: it converts each .msg/.srv/.action to
.idl with ``rosidl_adapter`` and hashes it with ``rosidl_generator_type_description``, exactly
as ``rosidl_generate_interfaces`` does, so a full check takes seconds.

Dependencies from other packages (std_msgs, geometry_msgs, ...) are read from the type
description JSON files the message wheels install into ``<venv>/share/<pkg>/``; local packages
are processed in dependency order so they can use each other's freshly computed descriptions.

Run it with the project venv's interpreter::

    .venv/bin/python scripts/check_interface_hashes.py            # all packages
    .venv/bin/python scripts/check_interface_hashes.py nav2_msgs  # one package

Exit status: 0 when every reference type of the checked packages exists with the reference
hash (and every dependency type found in the venv matches too), 1 otherwise.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import sys
import tempfile
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
INTERFACES = ROOT / "interfaces"
DEFAULT_REFERENCE = INTERFACES / "type_hashes.json"
INTERFACE_KINDS = {"msg": ".msg", "srv": ".srv", "action": ".action"}
DEPEND_TAGS = ("depend", "build_depend")


@dataclass
class Report:
    """Outcome of comparing computed hashes with the reference."""

    matched: list[str] = field(default_factory=list)
    mismatched: list[str] = field(default_factory=list)
    missing: list[str] = field(default_factory=list)
    unexpected: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return not (self.mismatched or self.missing or self.unexpected)


def local_packages(interfaces: Path) -> dict[str, Path]:
    """Map package name -> directory for every folder of ``interfaces`` holding a package.xml."""
    packages = {}
    for manifest in sorted(interfaces.glob("*/package.xml")):
        name = ET.parse(manifest).getroot().findtext("name")
        if not name:
            raise ValueError(f"{manifest}: <name> is missing or empty")
        packages[name.strip()] = manifest.parent
    return packages


def dependency_order(packages: dict[str, Path], targets: list[str] | None = None) -> list[str]:
    """Order ``targets`` (default: all) and the local packages they need, dependencies first."""
    local_deps = {}
    for name, path in packages.items():
        root = ET.parse(path / "package.xml").getroot()
        deps = {(el.text or "").strip() for tag in DEPEND_TAGS for el in root.iter(tag)}
        local_deps[name] = sorted(deps & packages.keys() - {name})
    ordered: list[str] = []
    visiting: set[str] = set()

    def visit(name: str) -> None:
        if name in ordered:
            return
        if name in visiting:
            raise ValueError(f"interfaces: dependency cycle through package '{name}'")
        visiting.add(name)
        for dep in local_deps[name]:
            visit(dep)
        visiting.discard(name)
        ordered.append(name)

    for name in sorted(targets or packages):
        visit(name)
    return ordered


def installed_include_paths(prefix: Path) -> dict[str, Path]:
    """Packages under ``<prefix>/share`` that install type description JSON files."""
    share = prefix / "share"
    if not share.is_dir():
        raise ValueError(f"{share} does not exist: is --prefix a ROS 2 venv?")
    return {
        pkg.name: pkg
        for pkg in sorted(share.iterdir())
        if any((pkg / kind).glob("*.json") for kind in INTERFACE_KINDS)
    }


def hash_package(name: str, package_dir: Path, include: dict[str, Path], work: Path) -> Path:
    """Convert one package to IDL, write its type description JSON files, return their folder."""
    from rosidl_adapter import convert_to_idl
    from rosidl_generator_type_description import generate_type_hash

    idl_root = work / "idl" / name
    json_root = work / "json" / name
    idl_tuples = []
    for kind, suffix in INTERFACE_KINDS.items():
        for source in sorted((package_dir / kind).glob(f"*{suffix}")):
            relative = source.relative_to(package_dir)
            chatter = io.StringIO()  # the adapter prints every file, and errors before raising them
            with contextlib.redirect_stdout(chatter), contextlib.redirect_stderr(chatter):
                try:
                    convert_to_idl(package_dir, name, relative, idl_root)
                except Exception as exc:
                    raise ValueError(f"{source}: cannot be parsed: {exc}") from exc
            idl_tuples.append(f"{idl_root}:{relative.with_suffix('.idl').as_posix()}")
    if not idl_tuples:
        raise ValueError(f"{package_dir}: no .msg, .srv or .action files found")
    arguments = {
        "package_name": name,
        "output_dir": str(json_root),
        "idl_tuples": idl_tuples,
        "include_paths": [f"{pkg}:{path}" for pkg, path in include.items() if pkg != name],
    }
    arguments_file = work / f"{name}_type_description_args.json"
    arguments_file.write_text(json.dumps(arguments))
    try:
        generate_type_hash(str(arguments_file))
    except KeyError as exc:
        raise ValueError(f"{package_dir}: refers to a type of unknown package {exc}") from exc
    except FileNotFoundError as exc:
        raise ValueError(f"{package_dir}: refers to a type that does not exist: {exc.filename}") from exc
    return json_root


def read_hashes(package_dir: Path) -> dict[str, str]:
    """All ``type_name -> RIHS01 hash`` pairs in a folder of type description JSON files."""
    hashes = {}
    for path in sorted(package_dir.glob("*/*.json")):
        for entry in json.loads(path.read_text()).get("type_hashes", []):
            hashes[entry["type_name"]] = entry["hash_string"]
    return hashes


def compute_hashes(interfaces: Path, prefix: Path, only: list[str] | None = None) -> dict[str, str]:
    """Hash every local package (and collect the installed dependency hashes) from source."""
    packages = local_packages(interfaces)
    unknown = sorted(set(only or []) - packages.keys())
    if unknown:
        raise ValueError(f"unknown package(s) {unknown}; found {sorted(packages)} in {interfaces}")
    include = installed_include_paths(prefix)
    for name in packages:
        include.pop(name, None)  # never mix in an installed copy of a package we build from source
    hashes: dict[str, str] = {}
    for path in include.values():
        hashes.update(read_hashes(path))
    with tempfile.TemporaryDirectory(prefix="check_interface_hashes_") as tmp:
        for name in dependency_order(packages, only):
            include[name] = hash_package(name, packages[name], include, Path(tmp))
            hashes.update(read_hashes(include[name]))
    return hashes


def compare(reference: dict[str, str], computed: dict[str, str], local: set[str]) -> Report:
    """Check every reference type; local packages must also define no type outside the reference.

    A reference type of a non-local package (a dependency such as std_msgs) counts as missing
    when the venv does not provide it, since the built interfaces could not be used then.
    """
    report = Report()
    for type_name, expected in sorted(reference.items()):
        actual = computed.get(type_name)
        if actual is None:
            report.missing.append(type_name)
        elif actual != expected:
            report.mismatched.append(type_name)
        else:
            report.matched.append(type_name)
    report.unexpected = sorted(
        t for t in computed if t.split("/")[0] in local and t not in reference
    )
    return report


def load_reference(path: Path) -> dict[str, str]:
    """Read ``{"hashes": {type_name: hash}}`` (or a bare mapping) from ``path``."""
    try:
        data = json.loads(path.read_text())
    except (OSError, json.JSONDecodeError) as exc:
        raise ValueError(f"{path}: cannot read reference hashes: {exc}") from exc
    hashes = data.get("hashes", data)
    if not isinstance(hashes, dict) or not all(isinstance(v, str) for v in hashes.values()):
        raise ValueError(f"{path}: expected a mapping of type names to RIHS01 hash strings")
    return hashes


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("packages", nargs="*", help="local packages to check (default: all)")
    parser.add_argument("--reference", type=Path, default=DEFAULT_REFERENCE, help="reference hash JSON")
    parser.add_argument("--interfaces", type=Path, default=INTERFACES, help="folder of interface packages")
    parser.add_argument("--prefix", type=Path, default=Path(sys.prefix),
                        help="prefix whose share/ holds the dependency packages (default: this venv)")
    parser.add_argument("-v", "--verbose", action="store_true", help="also list matching types")
    args = parser.parse_args(argv)
    try:
        import rosidl_adapter  # noqa: F401
        import rosidl_generator_type_description  # noqa: F401
    except ImportError:
        parser.error("rosidl_adapter is not importable: run this with the project venv (.venv/bin/python)")
    try:
        reference = load_reference(args.reference)
        computed = compute_hashes(args.interfaces, args.prefix, args.packages or None)
    except ValueError as exc:
        print(f"check_interface_hashes: {exc}", file=sys.stderr)
        return 1
    local = set(args.packages) if args.packages else set(local_packages(args.interfaces))
    if args.packages:  # skip reference types of local packages that were not asked for
        others = set(local_packages(args.interfaces)) - local
        reference = {k: v for k, v in reference.items() if k.split("/")[0] not in others}
    report = compare(reference, computed, local)
    for label, names in (("MISMATCH", report.mismatched), ("MISSING", report.missing),
                         ("UNEXPECTED", report.unexpected)):
        for name in names:
            detail = f"ours {computed[name]} != reference {reference[name]}" if label == "MISMATCH" else ""
            print(f"{label:10} {name} {detail}".rstrip())
    if args.verbose:
        for name in report.matched:
            print(f"{'ok':10} {name}")
    print(
        f"{len(report.matched)}/{len(reference)} reference types match; {len(report.mismatched)} mismatched, "
        f"{len(report.missing)} missing, {len(report.unexpected)} not in the reference"
    )
    return 0 if report.ok else 1


if __name__ == "__main__":
    sys.exit(main())
