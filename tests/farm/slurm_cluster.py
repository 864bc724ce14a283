"""A private single-node Slurm cluster for tests: munged, slurmctld and slurmd
started in a temporary folder with their own ports, socket, state and spool,
and stopped by their PIDs whatever happens (docs/farm.md, "Testing")."""
import atexit
import os
import pwd
import shutil
import signal
import socket
import subprocess
import tempfile
import time


def _free_ports(n):
    sockets = [socket.socket() for _ in range(n)]
    for s in sockets:
        s.bind(("127.0.0.1", 0))
    ports = [s.getsockname()[1] for s in sockets]
    for s in sockets:
        s.close()
    return ports


def unavailable_reason():
    """Why a private cluster cannot start here, or None."""
    for program in ("munged", "mungekey", "slurmctld", "slurmd", "sbatch", "runuser"):
        if not shutil.which(program, path=os.environ.get("PATH", "") + ":/usr/sbin:/sbin"):
            return f"{program} not found (scripts/install-deps installs slurm-wlm and munge)"
    if os.geteuid() != 0:
        return "slurmd and munged (as user munge) need root"
    try:
        pwd.getpwnam("munge")
    except KeyError:
        return "no user munge (the munge package creates it)"
    return None


class SlurmCluster:
    def __init__(self):
        self.dir = tempfile.mkdtemp(prefix="loom-slurm-")
        os.chmod(self.dir, 0o755)
        self.pids = []
        atexit.register(self.stop)

    def _sbin(self, name):
        return shutil.which(name, path=os.environ.get("PATH", "") + ":/usr/sbin:/sbin")

    def _start_munge(self):
        d = os.path.join(self.dir, "munge")
        os.mkdir(d)
        shutil.chown(d, "munge", "munge")
        os.chmod(d, 0o711)  # clients reach the socket; only munge writes here
        key = os.path.join(d, "munge.key")
        # A key of our own, made as the package's postinst makes /etc/munge/munge.key.
        subprocess.run([self._sbin("runuser"), "-u", "munge", "--", self._sbin("mungekey"), "--create", "--keyfile", key],
                       check=True, capture_output=True)
        self.munge_socket = os.path.join(d, "munge.socket")
        subprocess.run([self._sbin("runuser"), "-u", "munge", "--", self._sbin("munged"), "--socket", self.munge_socket,
                        "--key-file", key, "--pid-file", os.path.join(d, "munged.pid"),
                        "--log-file", os.path.join(d, "munged.log"), "--seed-file", os.path.join(d, "seed")],
                       check=True, capture_output=True)
        self._remember(os.path.join(d, "munged.pid"))

    def _remember(self, pid_file, timeout=10):
        deadline = time.time() + timeout
        while time.time() < deadline:
            try:
                with open(pid_file) as f:
                    self.pids.append(int(f.read().strip()))
                    return
            except (OSError, ValueError):
                time.sleep(0.05)
        raise RuntimeError(f"{pid_file} never appeared: see the logs in {self.dir}")

    def _write_conf(self):
        ctld, slurmd = _free_ports(2)
        d = self.dir
        for sub in ("state", "spool", "log"):
            os.mkdir(os.path.join(d, sub))
        cpus = os.cpu_count() or 1
        conf = f"""ClusterName=loomtest{ctld}
SlurmctldHost=localhost
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket={self.munge_socket}
CredType=cred/munge
SlurmctldPort={ctld}
SlurmdPort={slurmd}
StateSaveLocation={d}/state
SlurmdSpoolDir={d}/spool
SlurmctldPidFile={d}/slurmctld.pid
SlurmdPidFile={d}/slurmd.pid
SlurmctldLogFile={d}/log/slurmctld.log
SlurmdLogFile={d}/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerParameters=batch_sched_delay=0,sched_min_interval=100000
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MpiDefault=none
ReturnToService=2
KillWait=10
NodeName=localhost CPUs={cpus} RealMemory=1000 State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
"""
        self.conf = os.path.join(d, "slurm.conf")
        with open(self.conf, "w") as f:
            f.write(conf)
        os.environ["SLURM_CONF"] = self.conf

    def start(self):
        self._start_munge()
        self._write_conf()
        subprocess.run([self._sbin("slurmctld"), "-f", self.conf, "-i"], check=True, capture_output=True)
        self._remember(os.path.join(self.dir, "slurmctld.pid"))
        subprocess.run([self._sbin("slurmd"), "-f", self.conf], check=True, capture_output=True)
        self._remember(os.path.join(self.dir, "slurmd.pid"))
        deadline = time.time() + 20
        while time.time() < deadline:
            out = subprocess.run(["sinfo", "-h", "-o", "%t"], capture_output=True, text=True).stdout.strip()
            if out in ("idle", "mix", "alloc"):
                return
            time.sleep(0.1)
        raise RuntimeError(f"the node never became idle: see {self.dir}/log")

    def wait_idle(self, timeout=60):
        """Waits until no job is queued or running."""
        deadline = time.time() + timeout
        while time.time() < deadline:
            out = subprocess.run(["squeue", "-h"], capture_output=True, text=True).stdout.strip()
            if not out:
                return
            time.sleep(0.1)
        raise TimeoutError("jobs still queued: " + out)

    def stop(self):
        for pid in reversed(self.pids):
            try:
                os.kill(pid, signal.SIGTERM)
            except ProcessLookupError:
                pass
        deadline = time.time() + 10
        for pid in self.pids:
            while time.time() < deadline and os.path.exists(f"/proc/{pid}") and not _zombie(pid):
                time.sleep(0.05)
            if os.path.exists(f"/proc/{pid}") and not _zombie(pid):
                os.kill(pid, signal.SIGKILL)
        self.pids = []
        os.environ.pop("SLURM_CONF", None)
        shutil.rmtree(self.dir, ignore_errors=True)


def _zombie(pid):
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().split(")")[-1].split()[0] == "Z"
    except OSError:
        return False
