#!/usr/bin/env python3
"""The renderer library writes no file and starts no process (issue 39): those are the harness's
(player/harness/, pnb_play_harness) and the tools'. Read from the static library's undefined
symbols with nm, so a call planted anywhere in pnb_player fails this test, whatever its path.

What is forbidden (FORBIDDEN below): opening a FILE stream or creating a file (fopen, freopen,
fdopen, tmpfile, creat, mkstemp), writing to a descriptor (write, pwrite, writev), renaming,
removing or creating names (rename, unlink, remove, mkdir, ...), starting a process (system,
popen, posix_spawn, fork, exec*), C++ output file streams (std::ofstream, std::fstream),
std::filesystem's calls that change the file system, and the format library's file writers
(pnb::writeFileAtomic, pnb::createTemporaryFor).

Allowed, on purpose: fwrite/fputs/fprintf (the renderer's notes go to stderr, and GCC turns a
constant fprintf(stderr, ...) into fwrite; with no way to open a FILE stream these can only reach
stdout/stderr), and open/read/ifstream (the renderer reads containers and /sys).

So that the scan cannot go blind (nm's output format, demangling, a wrong file), the harness
library is scanned too and must show the calls it is known to make (system, rename,
std::filesystem::create_directories, std::ofstream, pnb::writeFileAtomic).

Usage: renderer_writes_test.py NM LIBPNB_PLAYER.a LIBPNB_PLAY_HARNESS.a
       renderer_writes_test.py NM LIB.a            # scan one library only (exit 1 on a hit)
"""
import re
import subprocess
import sys

C_CALLS = ("fopen fopen64 freopen freopen64 fdopen tmpfile tmpfile64 creat creat64 mkstemp "
           "mkstemp64 mkstemps mkostemp mkostemps mkdtemp write pwrite pwrite64 writev pwritev "
           "rename renameat renameat2 unlink unlinkat remove rmdir mkdir mkdirat truncate "
           "truncate64 ftruncate ftruncate64 symlink symlinkat link linkat chmod fchmod "
           "system popen posix_spawn posix_spawnp fork vfork execl execle execlp execv execve "
           "execvp execvpe fexecve").split()
FS_CALLS = ("create_directory create_directories create_hard_link create_symlink "
            "create_directory_symlink copy copy_file copy_symlink remove remove_all rename "
            "resize_file permissions").split()
FORBIDDEN = [
    re.compile(r"^(?:%s)(?:@.*)?$" % "|".join(C_CALLS)),
    re.compile(r"^std::filesystem::(?:__cxx11::)?(?:%s)\(" % "|".join(FS_CALLS)),
    re.compile(r"^std::basic_(?:ofstream|fstream)<"),
    re.compile(r"^pnb::(?:writeFileAtomic|createTemporaryFor)\("),
]
# What the harness is known to call: the scan must find each, or it is blind.
HARNESS_KNOWN = ["system", "rename", "std::filesystem::create_directories(",
                 "std::basic_ofstream<", "pnb::writeFileAtomic("]


def undefined_symbols(nm, library):
    """[(object, demangled name)] of every undefined symbol in the archive."""
    out = subprocess.run([nm, "-A", "-C", "-u", library], capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit("FAIL: %s -A -C -u %s exited %d: %s" % (nm, library, out.returncode, out.stderr.strip()))
    symbols = []
    for line in out.stdout.splitlines():
        # "lib.a:member.o:                 U name(args)"; the name may itself contain ':'.
        m = re.match(r"^[^:]*:([^:]+):\s+U\s+(.+)$", line)
        if m:
            symbols.append((m.group(1), m.group(2).strip()))
    return symbols


def forbidden(symbols):
    return sorted({(obj, name) for obj, name in symbols if any(p.search(name) for p in FORBIDDEN)})


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    nm, renderer = sys.argv[1], sys.argv[2]
    failures = []
    symbols = undefined_symbols(nm, renderer)
    # The renderer draws with GL through epoxy: no epoxy symbol means nm read the wrong thing.
    if not any(name.startswith("epoxy_") for _, name in symbols):
        failures.append("%s: no epoxy_ symbol among %d undefined ones: not the renderer library?"
                        % (renderer, len(symbols)))
    hits = forbidden(symbols)
    for obj, name in hits:
        failures.append("%s: %s calls %s" % (renderer, obj, name))
    if len(sys.argv) == 4:
        harness = sys.argv[3]
        found = {name for _, name in forbidden(undefined_symbols(nm, harness))}
        for known in HARNESS_KNOWN:
            if not any(name == known or name.startswith(known) for name in found):
                failures.append("%s: the scan does not find %s, which the harness calls: the check "
                                "is blind" % (harness, known))
    for f in failures:
        print("FAIL: " + f)
    if failures:
        print("the renderer library must not write files or start processes: move the call to "
              "player/harness/ (pnb_play_harness) or give the renderer a callback (see "
              "ProgramCacheStore in pnb_player/program_cache.h)")
        return 1
    print("ok: %s: %d undefined symbols, none writes a file or starts a process" % (renderer, len(symbols)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
