"""pnb-sweep's outputs never replace its inputs, and two outputs are never one file: the rule of
pnb/output_guard.h for the Python tools. Two names are one file when they are the same inode
(hard links, symlinks, "./x" and "x") or, for a file that does not exist yet, the same path once
symlinked directories are resolved (os.path.realpath)."""
import os


def _place(path):
    try:
        st = os.stat(path)
        inode = (st.st_dev, st.st_ino)
    except OSError:
        inode = None
    return inode, os.path.realpath(path)


def check_outputs(inputs, outputs):
    """inputs, outputs: lists of (path, role). Returns None, or the message naming both files."""
    placed_in = [(_place(p), p, role) for p, role in inputs if p]
    placed_out = []
    for path, role in outputs:
        if not path:
            continue
        here = _place(path)
        for (there, other, other_role) in placed_in + placed_out:
            same = here[0] == there[0] if here[0] and there[0] else here[1] == there[1]
            if same:
                return ("%s '%s' is the same file as %s '%s' (%s): writing it would replace it. "
                        "Choose another output" % (role, path, other_role, other, here[1]))
        placed_out.append((here, path, role))
    return None


def write_atomically(path, text):
    """Writes `text` beside `path` and renames it over: readers see the old file or the new."""
    tmp = "%s.tmp.%d" % (path, os.getpid())
    try:
        with open(tmp, "w", newline="") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
