#!/usr/bin/env python3
"""Conformance over the real corpus of Debian's assimp-testmodels.

Runs `pnb-convert --test DIR` for each corpus folder: every file must either convert and pass
the container verification (pnb-inspect --verify's checks) or fail with a one-line error; a
crash ends the run and fails the test. Results are compared with the checked-in expectation list
so regressions (and improvements) show.

    conformance.py PNB_CONVERT EXPECTED.tsv            # check
    conformance.py PNB_CONVERT EXPECTED.tsv --update   # rewrite the list after a deliberate change
"""
import subprocess
import sys

ROOT = "/usr/share/assimp/models"
FOLDERS = ["OBJ", "glTF", "glTF2"]


def run(converter):
    results = {}
    for folder in FOLDERS:
        proc = subprocess.run([converter, "--test", f"{ROOT}/{folder}", "--quiet"],
                              capture_output=True, text=True, timeout=1200)
        if proc.returncode != 0:
            sys.exit(f"pnb-convert --test {folder} exited with {proc.returncode} "
                     f"(a crash?):\n{proc.stderr[-4000:]}")
        for line in proc.stdout.splitlines():
            if "\t" not in line:
                continue
            path, outcome = line.split("\t", 1)
            words = outcome.split()
            if words[0] == "ok":
                results[f"{folder}/{path}"] = "ok"
            elif words[0] == "error":
                results[f"{folder}/{path}"] = "error " + words[1].rstrip(":")
            else:  # "VERIFY FAILED": a written container that does not verify is always a bug
                results[f"{folder}/{path}"] = "verify-failed"
            if words[0] != "ok":
                print(f"{folder}/{path}: {outcome}")
    return results


def main():
    converter, expected_path = sys.argv[1], sys.argv[2]
    results = run(converter)
    if "--update" in sys.argv:
        with open(expected_path) as f:
            header = [l for l in f if l.startswith("#")]
        with open(expected_path, "w") as f:
            f.writelines(header)
            for path in sorted(results):
                f.write(f"{path}\t{results[path]}\n")
        print(f"updated {expected_path}: {len(results)} files")
        return 0
    expected = {}
    with open(expected_path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            path, outcome = line.rstrip("\n").split("\t")
            expected[path] = outcome
    failures = []
    for path in sorted(set(expected) | set(results)):
        want, got = expected.get(path, "(not listed)"), results.get(path, "(not run)")
        if want != got:
            failures.append(f"{path}: expected {want}, got {got}")
    ok = sum(1 for r in results.values() if r == "ok")
    print(f"{len(results)} files: {ok} converted and verified, {len(results) - ok} clean errors")
    if failures:
        print("MISMATCHES:\n  " + "\n  ".join(failures))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
