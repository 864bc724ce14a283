#!/usr/bin/env python3
"""A private multi-node Slurm cluster on one machine, for tests (docs/farm.md,
"Several nodes: a cluster of namespaces"): every node is a Linux network namespace joined to
a bridge by a veth pair, with its own hostname (UTS namespace), its own /tmp,
/dev/shm and install folder (mount namespace) and its own processes (PID
namespace, whose PID 1 runs slurmd). munged and slurmctld run on the host.

Addresses come from a /24 of 10.213.0.0/16 that no interface of the host uses;
the namespaces have no default route, so their traffic stays on the bridge,
between them and the host. Everything is stopped by PID; the namespaces and
the bridge are deleted; those left by a run that was killed are cleaned when
the next one starts. A node is stopped as a crash: SIGKILL to every process of
its PID namespace (its PID 1 ignores SIGTERM, as any namespace's PID 1 does
without a handler)."""
import atexit
import glob
import ipaddress
import os
import re
import shutil
import signal
import socket
import subprocess
import tempfile
import time

import slurm_cluster

PREFIX = "lm"  # lm<pid>n<k>: a node's namespace; lm<pid>br: the bridge; lm<pid>v<k>: its veth end
SHARED_ROOT = "/var/tmp"  # not /tmp: every node has its own /tmp
_NAME = re.compile(r"^" + PREFIX + r"(\d+)(?:n\d+|br|v\d+)$")


def _run(*argv, check=True):
    p = subprocess.run(list(argv), capture_output=True, text=True)
    if check and p.returncode != 0:
        raise RuntimeError(f"{' '.join(argv)}: exit {p.returncode}: {p.stderr.strip()}")
    return p


def _alive(pid):
    return os.path.exists(f"/proc/{pid}") and not slurm_cluster._zombie(pid)


def _pid_namespace(pid):
    try:
        return os.readlink(f"/proc/{pid}/ns/pid")
    except OSError:
        return None


def pids_in_namespace(ns, kind="pid"):
    """Every process whose `kind` namespace is `ns` (as /proc/PID/ns/KIND reads)."""
    out = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                if os.readlink(f"/proc/{entry}/ns/{kind}") == ns:
                    out.append(int(entry))
            except OSError:
                pass
    return out


def unavailable_reason():
    """Why the cluster cannot start here, or None."""
    reason = slurm_cluster.unavailable_reason()
    if reason:
        return reason
    for program in ("ip", "nsenter", "unshare"):
        if not shutil.which(program, path=os.environ.get("PATH", "") + ":/usr/sbin:/sbin"):
            return f"{program} not found (iproute2, util-linux)"
    probe = f"{PREFIX}{os.getpid()}probe"[:15]
    p = _run("ip", "link", "add", probe, "type", "bridge", check=False)
    if p.returncode != 0:
        return "cannot make a bridge (no CAP_NET_ADMIN?): " + p.stderr.strip()
    _run("ip", "link", "del", probe, check=False)
    p = _run("unshare", "--net", "--uts", "--mount", "--pid", "--fork", "true", check=False)
    if p.returncode != 0:
        return "cannot make namespaces: " + p.stderr.strip()
    return None


def clean_stale():
    """Removes what a killed run left: its nodes' processes, namespaces, bridge,
    veths, daemons and folder (the pid in the names has exited)."""
    dead = lambda pid: not _alive(int(pid))
    for ns in _run("ip", "netns", "list", check=False).stdout.split("\n"):
        name = ns.split(" ")[0]
        m = _NAME.match(name)
        if m and dead(m.group(1)):
            for pid in _run("ip", "netns", "pids", name, check=False).stdout.split():
                _kill(int(pid))
            _run("ip", "netns", "del", name, check=False)
    for line in _run("ip", "-o", "link", "show", check=False).stdout.split("\n"):
        parts = line.split(": ")
        name = parts[1].split("@")[0] if len(parts) > 1 else ""
        m = _NAME.match(name)
        if m and dead(m.group(1)):
            _run("ip", "link", "del", name, check=False)
    for folder in glob.glob(os.path.join(SHARED_ROOT, "loom-netns-*")):
        m = re.search(r"loom-netns-(\d+)-", folder)
        if not m or not dead(m.group(1)):
            continue
        for pid_file in glob.glob(os.path.join(folder, "*.pid")) + glob.glob(os.path.join(folder, "munge", "*.pid")):
            try:
                with open(pid_file) as f:
                    pid = int(f.read().strip())
                with open(f"/proc/{pid}/cmdline") as f:
                    if folder in f.read().replace("\0", " "):
                        _kill(pid)
            except (OSError, ValueError):
                pass
        shutil.rmtree(folder, ignore_errors=True)


def _kill(pid):
    try:
        os.kill(pid, signal.SIGKILL)
    except ProcessLookupError:
        pass


def _free_subnet():
    used = []
    for line in _run("ip", "-o", "-4", "addr", "show", check=False).stdout.split("\n"):
        m = re.search(r"inet (\S+)", line)
        if m:
            used.append(ipaddress.ip_interface(m.group(1)).network)
    for line in _run("ip", "-4", "route", "show", check=False).stdout.split("\n"):
        m = re.match(r"(\d+\.\d+\.\d+\.\d+/\d+)", line)
        if m:
            used.append(ipaddress.ip_network(m.group(1), strict=False))
    start = os.getpid() % 250
    for i in range(250):
        net = ipaddress.ip_network(f"10.213.{(start + i) % 250}.0/24")
        if not any(net.overlaps(u) for u in used):
            return net
    raise RuntimeError("no free /24 in 10.213.0.0/16")


class Node:
    def __init__(self, cluster, k):
        self.k = k
        self.name = f"n{k}"
        self.netns = f"{cluster.tag}n{k}"
        self.veth = f"{cluster.tag}v{k}"
        self.addr = str(cluster.net[10 + k])
        self.install = f"/opt/loom-{self.name}"  # where the node sees its own Loom
        self.unshare = None  # the host process that holds the node's namespaces
        self.pid_ns = None


class NetnsCluster(slurm_cluster.SlurmCluster):
    """Usage: c = NetnsCluster(3, install=BUILD_DIR); c.start(); ...; c.stop().
    `install`: a folder every node sees at its own path, /opt/loom-nK (read-only),
    with `loom` on the node's PATH (/usr/local/bin/loom in the node): nodes
    with Loom installed at different prefixes. `hide`: folders the nodes see
    empty (the submitting machine's install, so that nothing runs it).
    `pid_ranges`: each node's PIDs from a range of its own (see _node_script).
    `shared`: a folder every node sees at the same path (/tmp is each node's own)."""

    def __init__(self, nodes=3, cpus=1, install=None, hide=(), pid_ranges=True):
        clean_stale()
        self.tag = f"{PREFIX}{os.getpid()}"
        self.dir = tempfile.mkdtemp(prefix=f"loom-netns-{os.getpid()}-", dir=SHARED_ROOT)
        os.chmod(self.dir, 0o755)
        self.shared = os.path.join(self.dir, "shared")  # what every node sees at the same path
        os.mkdir(self.shared)
        self.pids = []
        self.cpus = cpus
        self.install = install
        self.hide = list(hide)
        self.pid_ranges = pid_ranges
        self.net = _free_subnet()
        self.host_addr = str(self.net[1])
        self.bridge = f"{self.tag}br"
        self.nodes = [Node(self, k) for k in range(1, nodes + 1)]
        self._made_bridge = False
        atexit.register(self.stop)

    def _write_conf(self):
        ctld, slurmd = slurm_cluster._free_ports(2)
        d = self.dir
        for sub in ("state", "log"):
            os.mkdir(os.path.join(d, sub))
        nodes = "\n".join(f"NodeName={n.name} NodeHostname={n.name} NodeAddr={n.addr} CPUs={self.cpus} "
                          f"RealMemory=1000 State=UNKNOWN" for n in self.nodes)
        names = ",".join(n.name for n in self.nodes)
        # JobRequeue, ReturnToService, the short timeouts and cred_expire: a job of
        # a lost node is requeued within seconds (cred_expire also delays a requeue).
        conf = f"""ClusterName=loomnet{ctld}
SlurmctldHost={socket.gethostname()}({self.host_addr})
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket={self.munge_socket},cred_expire=5
CredType=cred/munge
SlurmctldPort={ctld}
SlurmdPort={slurmd}
StateSaveLocation={d}/state
SlurmdSpoolDir=/tmp/slurmd
SlurmctldPidFile={d}/slurmctld.pid
SlurmdPidFile=/tmp/slurmd.pid
SlurmctldLogFile={d}/log/slurmctld.log
SlurmdLogFile={d}/log/slurmd-%n.log
SlurmdParameters=config_overrides
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerParameters=batch_sched_delay=0,sched_min_interval=100000,sched_interval=1,bf_interval=1
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MpiDefault=none
JobRequeue=1
ReturnToService=2
SlurmdTimeout=5
MessageTimeout=5
KillWait=5
{nodes}
PartitionName=debug Nodes={names} Default=YES MaxTime=INFINITE State=UP
"""
        self.conf = os.path.join(d, "slurm.conf")
        with open(self.conf, "w") as f:
            f.write(conf)
        os.environ["SLURM_CONF"] = self.conf

    def _make_network(self):
        _run("ip", "link", "add", self.bridge, "type", "bridge")
        self._made_bridge = True
        _run("ip", "addr", "add", f"{self.host_addr}/{self.net.prefixlen}", "dev", self.bridge)
        _run("ip", "link", "set", self.bridge, "up")
        for n in self.nodes:
            _run("ip", "netns", "add", n.netns)
            _run("ip", "link", "add", n.veth, "type", "veth", "peer", "name", "eth0", "netns", n.netns)
            _run("ip", "link", "set", n.veth, "master", self.bridge, "up")
            _run("ip", "-n", n.netns, "addr", "add", f"{n.addr}/{self.net.prefixlen}", "dev", "eth0")
            _run("ip", "-n", n.netns, "link", "set", "eth0", "up")
            _run("ip", "-n", n.netns, "link", "set", "lo", "up")

    def _node_script(self, n):
        lines = ["set -e", f"hostname {n.name}", "mount -t tmpfs tmpfs /tmp", "mount -t tmpfs tmpfs /dev/shm"]
        # Each node's PIDs from a range of its own, as separate machines' mostly
        # differ: fresh PID namespaces would give every node the same PIDs in the
        # same order, and the nodes then did not register (seen once: every node
        # stayed `unk*`). Loom's own staging files no longer depend on it: they
        # hold a random part besides the pid (engine/core/temporary_file.cpp).
        if self.pid_ranges:
            with open("/proc/sys/kernel/pid_max") as f:
                span = int(f.read()) // (len(self.nodes) + 1)
            lines.append(f"echo {n.k * span} > /proc/sys/kernel/ns_last_pid")
        if self.install:
            # The node's own install folder and a `loom` on its PATH (as a site's
            # /usr/local/bin), hidden from the host and the other nodes.
            lines += ["mount -t tmpfs tmpfs /opt", f"mkdir {n.install}",
                      f"mount --bind -o ro '{self.install}' {n.install}",
                      "mount -t tmpfs tmpfs /usr/local/bin", f"ln -s {n.install}/bin/loom /usr/local/bin/loom"]
        lines += [f"mount -t tmpfs -o ro tmpfs '{folder}'" for folder in self.hide]
        # ip netns exec would remount /sys, on which slurmd 22.05's cgroup code dies.
        lines += [f"{self._sbin('slurmd')} -D -f {self.conf} -N {n.name} &", "wait"]
        return "\n".join(lines)

    def start_node(self, n):
        log = open(os.path.join(self.dir, "log", f"node-{n.name}.out"), "ab")
        n.unshare = subprocess.Popen(
            ["nsenter", f"--net=/run/netns/{n.netns}", "--", "unshare", "--uts", "--mount", "--pid", "--fork",
             "--mount-proc", "--propagation", "private", "--", "/bin/sh", "-c", self._node_script(n)],
            stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL)
        log.close()
        deadline = time.time() + 10
        while time.time() < deadline and not n.pid_ns:
            try:
                with open(f"/proc/{n.unshare.pid}/task/{n.unshare.pid}/children") as f:
                    child = int(f.read().split()[0])
                ns = _pid_namespace(child)
                if ns and ns != _pid_namespace(os.getpid()):
                    n.pid_ns = ns
            except (OSError, IndexError, ValueError):
                time.sleep(0.02)
        if not n.pid_ns:
            raise RuntimeError(f"node {n.name} did not start: see {self.dir}/log")

    def kill_node(self, n):
        """The node crashes: SIGKILL to every process of its PID namespace."""
        for pid in pids_in_namespace(n.pid_ns):
            _kill(pid)
        if n.unshare:
            n.unshare.wait(timeout=10)
            n.unshare = None
        n.pid_ns = None

    def node_states(self):
        out = _run("sinfo", "-h", "-N", "-o", "%N %t", check=False).stdout
        return dict(line.split() for line in out.strip().split("\n") if line.strip())

    def wait_nodes(self, states=("idle", "mix", "alloc"), nodes=None, timeout=30):
        want = [n.name for n in (nodes or self.nodes)]
        deadline = time.time() + timeout
        while time.time() < deadline:
            st = self.node_states()
            if all(st.get(name, "").rstrip("*~#") in states for name in want):
                return
            time.sleep(0.1)
        raise RuntimeError(f"nodes {want} not {states}: {self.node_states()} (see {self.dir}/log)")

    def start(self):
        self._start_munge()
        self._write_conf()
        self._make_network()
        subprocess.run([self._sbin("slurmctld"), "-f", self.conf, "-i"], check=True, capture_output=True)
        self._remember(os.path.join(self.dir, "slurmctld.pid"))
        for n in self.nodes:
            self.start_node(n)
        self.wait_nodes()

    def restart_node(self, n):
        """Starts a killed node again (same address, fresh /tmp); Slurm returns it to service."""
        self.start_node(n)
        self.wait_nodes(nodes=[n])

    def stop(self):
        for n in self.nodes:
            if n.pid_ns:
                self.kill_node(n)
        slurm_cluster.SlurmCluster.stop(self)  # slurmctld and munged by PID, then the folder
        for n in self.nodes:
            _run("ip", "netns", "del", n.netns, check=False)
        if self._made_bridge:
            _run("ip", "link", "del", self.bridge, check=False)
            self._made_bridge = False


def main():
    """Try a job on several nodes before a real cluster (docs/farm.md):
    netns_cluster.py [--nodes N] [--install BUILD] [-- COMMAND...] starts the
    cluster, runs COMMAND (default: a shell) with SLURM_CONF set and
    LOOM_CLUSTER_SHARED naming a folder every node sees, then stops it all."""
    import argparse
    import sys
    parser = argparse.ArgumentParser(description=main.__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--nodes", type=int, default=3)
    parser.add_argument("--cpus", type=int, default=1, help="slots per node")
    parser.add_argument("--install", help="a Loom build or install folder (with bin/loom): each node's own copy")
    parser.add_argument("command", nargs="*", default=[os.environ.get("SHELL", "/bin/sh")])
    args = parser.parse_args()
    reason = unavailable_reason()
    if reason:
        sys.exit(f"cannot start the cluster: {reason}")
    cluster = NetnsCluster(args.nodes, args.cpus, os.path.abspath(args.install) if args.install else None)
    try:
        start = time.time()
        cluster.start()
        os.environ["LOOM_CLUSTER_SHARED"] = cluster.shared
        print(f"{args.nodes} nodes up in {time.time() - start:.1f} s: {cluster.node_states()}; "
              f"SLURM_CONF={cluster.conf}; shared folder: {cluster.shared} ($LOOM_CLUSTER_SHARED)", file=sys.stderr)
        code = subprocess.call(args.command)
    finally:
        cluster.stop()
    sys.exit(code)


if __name__ == "__main__":
    main()
