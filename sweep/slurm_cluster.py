"""A single-node Slurm cluster on loopback, started by a test and stopped by it.

    with LocalSlurmCluster() as cluster:          # raises ClusterUnavailable(reason)
        job = cluster.submit_array("task.sh", 4, throttle=2)
        states = cluster.wait([job], timeout=30)   # {"12_0": "COMPLETED", ...}

Everything lives in one temporary directory: a munge key made for the cluster, munged with its own
socket, a generated slurm.conf (free TCP ports on 127.0.0.1, state, spool, logs and pid files in the
directory), slurmctld and slurmd in the foreground as child processes. The daemons are stopped by
their own PIDs (SIGTERM, then SIGKILL after a timeout); nothing is looked up by name. Client
commands get `SLURM_CONF` through `cluster.env` (or `cluster.run`). No cgroups, no accounting
database, no system paths beyond the binaries Debian installs (slurm-wlm, munge).

Python 3.11 standard library only. See docs/SWEEP.md.
"""
from __future__ import annotations

import os
import secrets
import shutil
import signal
import socket
import subprocess
import tempfile
import time
from pathlib import Path

__all__ = ["ClusterUnavailable", "LocalSlurmCluster"]

BINARIES = ("munged", "slurmctld", "slurmd", "sbatch", "squeue", "scancel", "sinfo", "scontrol")
# A Unix socket path is at most 107 bytes; slurmstepd puts "<node>_<job>.<step>" sockets in
# SlurmdSpoolDir, so the socket-bearing directories must have short paths.
_MAX_SOCKET_DIR = 64
# squeue's default state filter: a job in one of these is not done yet.
_ACTIVE_STATES = {"PENDING", "RUNNING", "SUSPENDED", "COMPLETING", "CONFIGURING", "REQUEUED",
                  "RESIZING", "SIGNALING", "STAGE_OUT", "STOPPED", "RESV_DEL_HOLD",
                  "REQUEUE_FED", "REQUEUE_HOLD", "SPECIAL_EXIT"}


class ClusterUnavailable(Exception):
    """The cluster cannot run here (a binary missing, a daemon that did not come up)."""

    def __init__(self, reason: str):
        super().__init__(reason)
        self.reason = reason


def _which(name: str) -> str | None:
    # Daemons live in /usr/sbin, which a non-root PATH often lacks.
    path = os.environ.get("PATH", "") + os.pathsep + "/usr/sbin:/sbin:/usr/local/sbin"
    return shutil.which(name, path=path)


def _free_ports(count: int) -> list[int]:
    """`count` distinct free TCP ports on 127.0.0.1 (held open together so they differ).
    Another process may take one before the daemon binds it: start() retries once on that."""
    socks = []
    try:
        for _ in range(count):
            s = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
            s.bind(("127.0.0.1", 0))
            socks.append(s)
        return [s.getsockname()[1] for s in socks]
    finally:
        for s in socks:
            s.close()


def _real_memory_mb() -> int:
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemTotal:"):
                    return max(64, int(line.split()[1]) // 1024 // 2)
    except OSError:
        pass
    return 512


def _tail(path: Path, lines: int = 12) -> str:
    try:
        text = path.read_text(errors="replace").splitlines()
    except OSError:
        return f"(no {path.name})"
    return "\n".join(f"    {line}" for line in text[-lines:])


class LocalSlurmCluster:
    """Context manager for a loopback Slurm cluster of one node (this machine, short hostname).

    workdir: the directory in which the cluster's temporary directory is made (default: the
      system's temporary directory). Its path must be traversable by all (munged checks it).
    cpus: CPUs of the node (default: os.cpu_count()).
    keep: leave the temporary directory after stop() (logs, slurm.conf) for a post-mortem.
    start_timeout: seconds for each daemon to come up before ClusterUnavailable.
    partition: the one partition's name (the default partition).
    """

    def __init__(self, workdir: str | os.PathLike | None = None, cpus: int | None = None, *,
                 keep: bool = False, start_timeout: float = 30.0, partition: str = "pnb"):
        self.workdir = Path(workdir) if workdir is not None else None
        self.cpus = cpus or os.cpu_count() or 1
        self.keep = keep
        self.start_timeout = start_timeout
        self.partition = partition
        self.nodename = socket.gethostname().split(".")[0]
        self.user = _user_name()
        self.root: Path | None = None       # the temporary directory
        self._sockdir: Path | None = None   # root, or a short directory in /tmp when root is long
        self.conf: Path | None = None
        self.env: dict[str, str] = {}
        self.bin: dict[str, str] = {}
        self.procs: dict[str, subprocess.Popen] = {}
        self.pids: dict[str, int] = {}      # daemon -> PID (Popen's, checked against the pid file)
        self.ports: dict[str, int] = {}
        self.cluster_name = f"pnb{secrets.token_hex(3)}"  # lower case, unique per instance
        self.stopped_pids: list[int] = []    # the daemons stop() ended
        self.killed_leftovers: list[int] = []  # processes of jobs that outlived the daemons

    # ---------------------------------------------------------------- life cycle
    def __enter__(self) -> "LocalSlurmCluster":
        self.start()
        return self

    def __exit__(self, *exc) -> None:
        self.stop()

    def start(self) -> None:
        missing = []
        for name in BINARIES:
            path = _which(name)
            if path is None:
                missing.append(name)
            else:
                self.bin[name] = path
        if missing:
            raise ClusterUnavailable(
                f"missing {', '.join(missing)} (Debian packages slurm-wlm and munge: scripts/setup)")
        try:
            self._make_dirs()
            self._start_munged()
            for attempt in range(2):
                try:
                    self._write_conf()
                    self._start_slurm()
                    break
                except ClusterUnavailable as e:
                    # A free port taken between choosing it and the daemon's bind: once more.
                    if attempt == 1 or "Address already in use" not in e.reason:
                        raise
                    self._stop_proc("slurmd")
                    self._stop_proc("slurmctld")
                    self._set_aside_attempt()
        except BaseException:
            self.stop()
            raise

    def stop(self) -> None:
        """Cancel this cluster's jobs, stop slurmd, slurmctld and munged by their own PIDs and
        remove the temporary directory (unless keep). Safe to call twice."""
        if "slurmctld" in self.procs and self.procs["slurmctld"].poll() is None and \
                "slurmd" in self.procs and self.procs["slurmd"].poll() is None:
            # Running tasks belong to slurmstepd processes that outlive slurmd: end them first.
            self.run(["scancel", "--partition", self.partition], check=False, timeout=10)
            deadline = time.monotonic() + 10
            while time.monotonic() < deadline and self._queue_ids([]):
                time.sleep(0.2)
            # A slurmstepd (and its task) can outlive the job's COMPLETED state by a moment while
            # it reports to slurmd: let it finish while slurmd is still there.
            deadline = time.monotonic() + 10
            while time.monotonic() < deadline and self._job_processes():
                time.sleep(0.1)
        for name in ("slurmd", "slurmctld", "munged"):
            self._stop_proc(name)
        # slurmctld's helper (slurmscriptd) ends after its parent, by a moment that grows under
        # load (a fresh-clone ASan run on 2 cores found one still there): a few seconds' grace.
        deadline = time.monotonic() + 5
        while time.monotonic() < deadline and self.leftover_processes():
            time.sleep(0.1)
        # Whatever still runs with this cluster's SLURM_CONF is a leak: ended by its own PID and
        # recorded (the test asserts there is none).
        for pid in self.leftover_processes():
            try:
                os.kill(pid, signal.SIGKILL)
                self.killed_leftovers.append(pid)
            except ProcessLookupError:
                pass
        if self.root is not None and not self.keep:
            shutil.rmtree(self.root, ignore_errors=True)
            if self._sockdir is not None and self._sockdir != self.root:
                shutil.rmtree(self._sockdir, ignore_errors=True)

    # ---------------------------------------------------------------- client helpers
    def run(self, args: list[str], *, check: bool = True, timeout: float = 30,
            cwd: str | os.PathLike | None = None) -> subprocess.CompletedProcess:
        """A client command (sbatch, squeue, ...) against this cluster; output as text."""
        args = [self.bin.get(args[0], args[0]), *map(str, args[1:])]
        return subprocess.run(args, env=self.env, cwd=cwd, capture_output=True, text=True,
                              check=check, timeout=timeout)

    def submit(self, args: list[str], cwd: str | os.PathLike | None = None) -> str:
        """`sbatch --parsable ARGS`; returns the job ID."""
        r = self.run(["sbatch", "--parsable", *args], check=False, cwd=cwd)
        if r.returncode != 0:
            raise RuntimeError(f"sbatch {' '.join(map(str, args))}: {r.stderr.strip()}")
        return r.stdout.strip().split(";")[0]

    def submit_array(self, script_path: str | os.PathLike, n: int | str,
                     throttle: int | None = None, extra_args: list[str] = (),
                     cwd: str | os.PathLike | None = None) -> str:
        """An array job of `n` tasks (0..n-1), or of the index list `n` when it is a string
        ("2", "0,3", "1-5"); at most `throttle` tasks at once. Returns the array's job ID."""
        spec = f"0-{int(n) - 1}" if isinstance(n, int) else n
        if throttle:
            spec += f"%{int(throttle)}"
        return self.submit([f"--array={spec}", *extra_args, str(script_path)], cwd=cwd)

    def wait(self, job_ids: list[str], timeout: float = 60, poll: float = 0.25) -> dict[str, str]:
        """Polls squeue until none of `job_ids` is pending or running; returns the final state of
        each job or array task ({"12": "COMPLETED", "13_2": "CANCELLED", ...}), as far as
        slurmctld still remembers (MinJobAge). TimeoutError if they are not done in time."""
        ids = [str(j) for j in job_ids]
        deadline = time.monotonic() + timeout
        while True:
            active = self._queue_ids(ids)
            if not active:
                return self.states(ids)
            if time.monotonic() > deadline:
                raise TimeoutError(f"jobs still active after {timeout} s: {sorted(active)}")
            time.sleep(poll)

    def states(self, job_ids: list[str]) -> dict[str, str]:
        """{job or array task ID: state} for `job_ids`, finished ones included."""
        r = self.run(["squeue", "-h", "-r", "-t", "all", "-j", ",".join(map(str, job_ids)),
                      "-o", "%i %T"], check=False)
        out = {}
        for line in r.stdout.splitlines():
            parts = line.split()
            if len(parts) == 2:
                out[parts[0]] = parts[1]
        return out

    def leftover_processes(self) -> list[int]:
        """PIDs of processes still running with this cluster's SLURM_CONF in their environment
        (job tasks that outlived the cluster). Empty after a clean stop()."""
        if self.conf is None:
            return []
        needle = f"SLURM_CONF={self.conf}".encode()
        found = []
        for entry in os.listdir("/proc"):
            if not entry.isdigit() or int(entry) == os.getpid():
                continue
            try:
                with open(f"/proc/{entry}/environ", "rb") as f:
                    if needle in f.read().split(b"\0"):
                        found.append(int(entry))
            except OSError:
                continue
        return found

    # ---------------------------------------------------------------- internals
    def _job_processes(self) -> list[int]:
        """leftover_processes() less the daemons and slurmctld's own helper (slurmscriptd)."""
        daemons = set(self.pids.values())
        jobs = []
        for pid in self.leftover_processes():
            try:
                with open(f"/proc/{pid}/stat") as f:
                    ppid = int(f.read().rpartition(")")[2].split()[1])
            except (OSError, ValueError, IndexError):
                continue
            if pid not in daemons and ppid != self.pids.get("slurmctld"):
                jobs.append(pid)
        return jobs

    def _queue_ids(self, ids: list[str]) -> set[str]:
        args = ["squeue", "-h", "-o", "%i"]
        if ids:
            args += ["-j", ",".join(ids)]
        else:
            args += ["-p", self.partition]
        r = self.run(args, check=False)
        if r.returncode != 0:
            if "Invalid job id" in r.stderr:  # purged after MinJobAge: done
                return set()
            raise RuntimeError(f"squeue: {r.stderr.strip()}")
        return set(r.stdout.split())

    def _make_dirs(self) -> None:
        if self.workdir is not None:
            self.workdir.mkdir(parents=True, exist_ok=True)
        self.root = Path(tempfile.mkdtemp(prefix="pnb-slurm-", dir=self.workdir)).resolve()
        # munged wants every directory above its socket searchable by all ("execute permissions
        # for all required") and none writable by others without the sticky bit: 0711 lets
        # clients reach the socket without listing the directory.
        os.chmod(self.root, 0o711)
        if len(str(self.root)) <= _MAX_SOCKET_DIR:
            self._sockdir = self.root
        else:
            self._sockdir = Path(tempfile.mkdtemp(prefix="pnb-slurm-")).resolve()
            os.chmod(self._sockdir, 0o711)
        for sub in ("state", "log"):
            (self.root / sub).mkdir(mode=0o700)
        (self._sockdir / "spool").mkdir(mode=0o700)

    def _set_aside_attempt(self) -> None:
        """Before a second start: the first attempt's logs renamed (so that its errors are not
        read as the new one's) and its state removed (slurmctld starts afresh)."""
        for name in ("slurmctld", "slurmd"):
            for suffix in (".log", ".stdout"):
                f = self.root / "log" / f"{name}{suffix}"
                if f.exists():
                    f.rename(f.with_name(f.name + ".attempt1"))
        for f in (self.root / "state").iterdir():
            if f.name != "munged.seed":
                shutil.rmtree(f) if f.is_dir() else f.unlink()

    def _start_munged(self) -> None:
        key = self.root / "munge.key"
        fd = os.open(key, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o400)
        with os.fdopen(fd, "wb") as f:
            f.write(secrets.token_bytes(1024))
        os.chmod(key, 0o400)  # owned by the running user: we created it
        self.munge_socket = self._sockdir / "munge.sock"
        args = [self.bin["munged"], "--foreground",
                f"--socket={self.munge_socket}", f"--key-file={key}",
                f"--pid-file={self.root / 'munged.pid'}",
                f"--log-file={self.root / 'log' / 'munged.log'}",
                f"--seed-file={self.root / 'state' / 'munged.seed'}"]
        self._spawn("munged", args)
        self._wait_for("munged", lambda: self.munge_socket.is_socket(),
                       self.root / "log" / "munged.log")
        self._check_pid_file("munged", self.root / "munged.pid")

    def _write_conf(self) -> None:
        ctld_port, d_port = _free_ports(2)
        self.ports = {"slurmctld": ctld_port, "slurmd": d_port}
        (self.root / "plugstack.conf").write_text("")  # not /etc/slurm/plugstack.conf's plugins
        r = self.root
        lines = [
            f"ClusterName={self.cluster_name}",
            "SlurmctldHost=localhost(127.0.0.1)",
            f"SlurmctldPort={ctld_port}",
            f"SlurmdPort={d_port}",
            f"SlurmUser={self.user}",
            f"SlurmdUser={self.user}",
            "AuthType=auth/munge",
            f"AuthInfo=socket={self.munge_socket}",
            "CredType=cred/munge",
            f"StateSaveLocation={r / 'state'}",
            f"SlurmdSpoolDir={self._sockdir / 'spool'}",
            f"SlurmctldPidFile={r / 'slurmctld.pid'}",
            f"SlurmdPidFile={r / 'slurmd.pid'}",
            f"SlurmctldLogFile={r / 'log' / 'slurmctld.log'}",
            f"SlurmdLogFile={r / 'log' / 'slurmd.log'}",
            "SlurmctldDebug=info",
            "SlurmdDebug=info",
            f"PlugStackConfig={r / 'plugstack.conf'}",
            "ProctrackType=proctrack/linuxproc",
            "TaskPlugin=task/none",
            "JobAcctGatherType=jobacct_gather/none",
            "AccountingStorageType=accounting_storage/none",
            "JobCompType=jobcomp/none",
            "SelectType=select/cons_tres",
            "SelectTypeParameters=CR_Core",
            "SchedulerType=sched/backfill",
            "ReturnToService=2",
            "MpiDefault=none",
            "SlurmdParameters=config_overrides",
            "KillWait=2",
            "MailProg=/bin/true",
            f"NodeName={self.nodename} NodeAddr=127.0.0.1 CPUs={self.cpus} "
            f"RealMemory={_real_memory_mb()} State=UNKNOWN",
            f"PartitionName={self.partition} Nodes=ALL Default=YES MaxTime=INFINITE State=UP",
        ]
        self.conf = r / "slurm.conf"
        self.conf.write_text("\n".join(lines) + "\n")
        env = {k: v for k, v in os.environ.items() if not k.startswith(("SLURM_", "SBATCH_",
               "SQUEUE_", "SINFO_", "SCONTROL_", "SCANCEL_", "SALLOC_", "SRUN_"))}
        env["SLURM_CONF"] = str(self.conf)
        self.env = env

    def _start_slurm(self) -> None:
        log = self.root / "log"
        self._spawn("slurmctld", [self.bin["slurmctld"], "-D", "-f", str(self.conf)])
        ping = lambda: "is UP" in self.run(["scontrol", "ping"], check=False, timeout=3).stdout
        self._wait_for("slurmctld", ping, log / "slurmctld.log")
        self._check_pid_file("slurmctld", self.root / "slurmctld.pid")
        self._spawn("slurmd", [self.bin["slurmd"], "-D", "-f", str(self.conf), "-N", self.nodename])

        def idle():
            states = self.run(["sinfo", "-h", "-o", "%T"], check=False, timeout=3).stdout.split()
            bad = [s for s in states if s.rstrip("*~#!%$@^-").lower() in
                   ("down", "drained", "draining", "fail", "inval")]
            if bad:
                reason = self.run(["sinfo", "-h", "-R"], check=False).stdout.strip()
                raise ClusterUnavailable(f"node {self.nodename} is {bad[0]}: {reason}\n"
                                         f"  slurmd log:\n{_tail(log / 'slurmd.log')}")
            return bool(states) and all(s.rstrip("*~#!%$@^-") == "idle" for s in states)

        self._wait_for("slurmd", idle, log / "slurmd.log")
        self._check_pid_file("slurmd", self.root / "slurmd.pid")

    def _spawn(self, name: str, args: list[str]) -> None:
        out = open(self.root / "log" / f"{name}.stdout", "ab")
        try:
            # Own session: a Ctrl-C in the terminal reaches the test, which then stops us itself.
            p = subprocess.Popen(args, stdin=subprocess.DEVNULL, stdout=out,
                                 stderr=subprocess.STDOUT, env=self.env or None,
                                 start_new_session=True)
        finally:
            out.close()
        self.procs[name] = p
        self.pids[name] = p.pid

    def _wait_for(self, name: str, ready, logfile: Path) -> None:
        p = self.procs[name]
        deadline = time.monotonic() + self.start_timeout
        while True:
            if p.poll() is not None:
                raise ClusterUnavailable(
                    f"{name} exited with {p.returncode} while starting\n  {name} log:\n"
                    f"{_tail(logfile)}\n{_tail(self.root / 'log' / f'{name}.stdout', 5)}")
            if "Address already in use" in _tail(logfile, 50):
                raise ClusterUnavailable(f"{name}: a port was taken (Address already in use)\n"
                                         f"  {name} log:\n{_tail(logfile)}")
            try:
                if ready():
                    return
            except subprocess.TimeoutExpired:
                pass  # a client command that hung (e.g. another server on the port): not ready
            if time.monotonic() > deadline:
                raise ClusterUnavailable(
                    f"{name} not ready after {self.start_timeout:.0f} s\n  {name} log:\n"
                    f"{_tail(logfile)}")
            time.sleep(0.2)

    def _check_pid_file(self, name: str, path: Path) -> None:
        # In the foreground the daemon is our child; its pid file must agree.
        try:
            pid = int(path.read_text().split()[0])
        except (OSError, ValueError, IndexError):
            return
        if pid != self.pids[name]:
            raise ClusterUnavailable(f"{name}: pid file {path} says {pid}, the child is "
                                     f"{self.pids[name]}")

    def _stop_proc(self, name: str, timeout: float = 10) -> None:
        p = self.procs.pop(name, None)
        if p is None:
            return
        if p.poll() is None:
            p.send_signal(signal.SIGTERM)
            try:
                p.wait(timeout)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait(5)
        self.stopped_pids.append(p.pid)


def _user_name() -> str:
    import pwd
    return pwd.getpwuid(os.getuid()).pw_name
