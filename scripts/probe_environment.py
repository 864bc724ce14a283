"""The probe's second half: hostile environments rather than hostile values.

Each family sets up a folder (symlinks, FIFOs, a cache folder with a user's
files, scene files that are memory bombs), runs `loom run` in it (under a
file-size or address-space limit, or with a signal sent mid-write) and checks
what is left on disk. Verdicts beyond the value probe's:

  escape       a file was written outside --out
  data-loss    a file Loom does not own was deleted or changed
  hang         the run did not end within the timeout (a FIFO opened)
  leftover     a staging file (.loomtmp-*) stayed behind
  half-written a write failed but the run said it succeeded, or a target
               file appeared although its write failed
  memory       the run needed more than the address-space limit (a bomb
               allocated before its limit was checked)
  unclear      the error message is a raw library text

Families: symlink, cache, fifo, signal, full-disk, scene-bomb, long-name.
"""
import json
import os
import resource
import signal
import struct
import subprocess
import tempfile
import time

CHECKER = {"board": {"type": "Checkerboard", "inputs": {"size": [64, 48], "cells": 4}}}
SPHERE = {"sphere": {"type": "UVSphere", "inputs": {"rings": 8, "segments": 16}}}
POINTS = {"emit": {"type": "MPMEmitBox", "inputs": {"count": 100, "sampling": "random"}},
          "step": {"type": "MPMStep", "inputs": {"state": {"from": "emit.particles"}, "resolution": 16}}}
# Each writer: the nodes that feed it, and its input.
WRITERS = {"SaveImage": (CHECKER, "image", "board.image", ".png"),
           "SaveMesh": (SPHERE, "mesh", "sphere.mesh", ".obj"),
           "SaveVideo": (CHECKER, "image", "board.image", ".mp4"),
           "SavePoints": (POINTS, "points", "step.points", ".ply")}
TRIANGLE = "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n"
MB = 1 << 20


def write(path, data):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(data.encode() if isinstance(data, str) else data)


def graph(nodes, frames=None):
    g = {"loom": 1, "nodes": nodes}
    if frames:
        g["time"] = {"start": 1, "end": frames, "fps": 24}
    return g


def writer_graph(writer, path, frames=None, feed=None):
    nodes, port, link, _ = WRITERS[writer]
    nodes = dict(feed or nodes)
    nodes["w"] = {"type": writer, "inputs": {port: {"from": link}, "path": path}}
    return graph(nodes, frames or (2 if writer == "SaveVideo" else None))


def staging(folder):
    """Staging files: .loomtmp-PID-N..., or Loom's older .NAME.tmpPID.N... naming."""
    return [os.path.join(r, n) for r, _, names in os.walk(folder) for n in names
            if n.startswith(".loomtmp") or (n.startswith(".") and ".tmp" in n)]


def png_header(width, height):
    return (b"\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR" + struct.pack(">II", width, height) + b"\x08\x02\0\0\0" +
            b"\0" * 1004)


def glb(json_doc, bin_bytes=b"", json_length=None):
    text = json.dumps(json_doc).encode()
    text += b" " * (-len(text) % 4)
    bin_bytes += b"\0" * (-len(bin_bytes) % 4)
    total = 12 + 8 + len(text) + (8 + len(bin_bytes) if bin_bytes else 0)
    out = b"glTF" + struct.pack("<II", 2, total) + struct.pack("<I", json_length or len(text)) + b"JSON" + text
    if bin_bytes:
        out += struct.pack("<I", len(bin_bytes)) + b"BIN\0" + bin_bytes
    return out


def triangle_gltf(extra=None, buffer_uri=None):
    doc = {"asset": {"version": "2.0"},
           "buffers": [{"byteLength": 36}],
           "bufferViews": [{"buffer": 0, "byteLength": 36}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                          "min": [0, 0, 0], "max": [1, 1, 0]}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
           "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}]}
    if buffer_uri:
        doc["buffers"][0]["uri"] = buffer_uri
    doc.update(extra or {})
    return doc


TRIANGLE_BIN = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)


def run_loom(loom, d, g, timeout, extra=(), limits=None, send=None):
    """Runs the graph; `send` is a list of signals sent once a staging file appears."""
    path = os.path.join(d, "g.json")
    write(path, json.dumps(g))
    def preexec():
        os.setsid()
        for what, value in (limits or {}).items():
            resource.setrlimit(what, (value, value))
    proc = subprocess.Popen([loom, "run", path, "--out", os.path.join(d, "out"), "--threads", "2", *extra],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, preexec_fn=preexec,
                            env=dict(os.environ, LOOM_PROGRESS="0", XDG_CACHE_HOME=os.path.join(d, "xdg")))
    if send:
        deadline = time.monotonic() + timeout
        while not staging(os.path.join(d, "out")) and time.monotonic() < deadline and proc.poll() is None:
            time.sleep(0.02)
        for s in send:
            if proc.poll() is None:
                proc.send_signal(s)
    try:
        output, _ = proc.communicate(timeout=timeout)
        return proc.returncode, output.decode("utf-8", "replace")
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        output, _ = proc.communicate()
        return None, output.decode("utf-8", "replace")


def family_symlink(loom, timeout):
    for writer, (_, _, _, ext) in WRITERS.items():
        for target in ("link/x", "link/sub/deep/y"):
            yield f"{writer} {target}{ext}", lambda c, w=writer, t=target + ext: symlink_case(c, loom, timeout, w, t)


def symlink_case(d, loom, timeout, writer, target):
    os.makedirs(os.path.join(d, "outside"))
    os.makedirs(os.path.join(d, "out"))
    os.symlink("../outside", os.path.join(d, "out", "link"))
    rc, text = run_loom(loom, d, writer_graph(writer, target), timeout)
    if os.listdir(os.path.join(d, "outside")):
        return "escape", rc, text
    # A literal path is refused when the graph is bound (exit 2), a linked one when the node runs (1).
    return ("ok" if rc in (1, 2) and "symbolic link" in text else "unclear"), rc, text


def family_cache(loom, timeout):
    yield "run --cache on a project folder", lambda c: cache_case(c, loom, timeout, ["run"])
    yield "cache clear on a project folder", lambda c: cache_case(c, loom, timeout, ["clear"])


def cache_case(d, loom, timeout, how):
    proj = os.path.join(d, "proj")
    files = {os.path.join(proj, ".env"): "SECRET=1", os.path.join(proj, "sub", ".gitignore"): "*"}
    old = time.time() - 7200
    for p, text in files.items():
        write(p, text)
        os.utime(p, (old, old))
    if how == ["run"]:
        rc, text = run_loom(loom, d, writer_graph("SaveImage", "x.png"), timeout, ["--cache", proj, "--cache-limit", "0.000001"])
    else:
        p = subprocess.run([loom, "cache", "clear", "--cache", proj], capture_output=True, text=True, timeout=timeout)
        rc, text = p.returncode, p.stdout + p.stderr
    lost = [p for p, t in files.items() if not os.path.exists(p) or open(p).read() != t]
    return ("data-loss" if lost else "ok"), rc, text


def family_fifo(loom, timeout):
    scenes = {
        "mtllib fifo.mtl": ("LoadScene", "scene.obj", {"scene.obj": "mtllib fifo.mtl\n" + TRIANGLE}),
        "map_Kd fifo.png": ("LoadScene", "scene.obj", {"scene.obj": "mtllib s.mtl\n" + TRIANGLE,
                                                       "s.mtl": "newmtl m\nmap_Kd fifo.png\n"}),
        "glTF buffer uri": ("LoadScene", "s.gltf", {"s.gltf": json.dumps(triangle_gltf(buffer_uri="fifo.bin"))}),
        "glTF image uri": ("LoadScene", "s.gltf", {"s.gltf": json.dumps(triangle_gltf(
            {"images": [{"uri": "fifo.png"}], "textures": [{"source": 0}],
             "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
             "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}]},
            buffer_uri="data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"))}),
        "LoadMesh fifo.obj": ("LoadMesh", "fifo.obj", {}),
        "LoadImage fifo.png": ("LoadImage", "fifo.png", {}),
    }
    for label, (node, path, files) in scenes.items():
        yield label, lambda c, n=node, p=path, f=files: fifo_case(c, loom, timeout, n, p, f)


def fifo_case(d, loom, timeout, node, path, files):
    for name in ("fifo.mtl", "fifo.png", "fifo.bin", "fifo.obj"):
        os.mkfifo(os.path.join(d, name))
    for name, text in files.items():
        write(os.path.join(d, name), text)
    output = {"LoadScene": "scene", "LoadMesh": "mesh", "LoadImage": "image"}[node]
    rc, text = run_loom(loom, d, graph({"n": {"type": node, "inputs": {"path": path}}}), timeout,
                        ["--target", "n." + output])
    if rc is None:
        return "hang", rc, text
    return ("ok" if "FIFO" in text else "unclear"), rc, text


def family_signal(loom, timeout):
    for label, signals in (("SIGHUP", [signal.SIGHUP]), ("SIGPIPE", [signal.SIGPIPE]),
                           ("SIGTERM twice", [signal.SIGTERM, signal.SIGTERM]), ("SIGINT", [signal.SIGINT])):
        yield f"SaveVideo, {label}", lambda c, s=signals: signal_case(c, loom, timeout, s)


def signal_case(d, loom, timeout, signals):
    feed = {"board": {"type": "Checkerboard", "inputs": {"size": [640, 480], "cells": 24}}}
    rc, text = run_loom(loom, d, writer_graph("SaveVideo", "twist.mp4", frames=3000, feed=feed), timeout,
                        send=signals)
    if rc is None:
        return "hang", rc, text
    if staging(os.path.join(d, "out")):
        return "leftover", rc, text
    return ("ok" if rc == 130 else "unclear"), rc, text


def family_full_disk(loom, timeout):
    for writer in WRITERS:
        yield f"{writer} over a 64 KB file-size limit", lambda c, w=writer: full_disk_case(c, loom, timeout, w)


def full_disk_case(d, loom, timeout, writer):
    big = {"SaveImage": {"noise": {"type": "Checkerboard", "inputs": {"size": [2048, 2048], "cells": 1000}}},
           "SaveMesh": {"sphere": {"type": "UVSphere", "inputs": {"rings": 200, "segments": 400}}},
           "SaveVideo": {"board": {"type": "Checkerboard", "inputs": {"size": [1024, 768], "cells": 300}}},
           "SavePoints": {"emit": {"type": "MPMEmitBox", "inputs": {"count": 200000, "sampling": "random"}},
                          "step": {"type": "MPMStep", "inputs": {"state": {"from": "emit.particles"}, "resolution": 16}}}}
    nodes, port, link, ext = WRITERS[writer]
    feed = big[writer]
    if writer == "SaveImage":
        link = "noise.image"
    g = writer_graph(writer, "x" + ext, frames=48 if writer == "SaveVideo" else None, feed=feed)
    g["nodes"]["w"]["inputs"][port] = {"from": link}
    rc, text = run_loom(loom, d, g, timeout, ["--no-cache"], limits={resource.RLIMIT_FSIZE: 64 * 1024})
    out = os.path.join(d, "out")
    if rc is None:
        return "hang", rc, text
    if staging(out):
        return "leftover", rc, text
    present = [n for n in ("x" + ext, "x.mtl") if os.path.exists(os.path.join(out, n))]
    if rc == 0 or present:
        return "half-written", rc, text
    return "ok", rc, text


def family_scene_bomb(loom, timeout):
    image = png_header(20000, 20000)
    textured = triangle_gltf({"images": [{"bufferView": 1, "mimeType": "image/png"}], "textures": [{"source": 0}],
                              "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
                              "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}]})
    textured["buffers"][0]["byteLength"] = 36 + len(image)
    textured["bufferViews"].append({"buffer": 0, "byteOffset": 36, "byteLength": len(image)})
    claiming = triangle_gltf()
    claiming["buffers"][0]["byteLength"] = 0xfffffff0
    doubling = triangle_gltf({"nodes": [{"children": [i + 1, i + 1]} for i in range(40)] + [{"mesh": 0}]})
    cases = {  # label: (files, scene, LoadScene's expected exit code, the limit its message names)
        "MTL texture declaring 20000x20000": ({"s.obj": "mtllib s.mtl\n" + TRIANGLE, "huge.png": image,
                                               "s.mtl": "newmtl m\nmap_Kd huge.png\n"}, "s.obj", 0, "more than the limit"),
        "GLB texture declaring 20000x20000": ({"s.glb": glb(textured, TRIANGLE_BIN + image)}, "s.glb", 0,
                                              "more than the limit"),
        "GLB JSON chunk of 0xfffffff0 bytes": ({"s.glb": glb(triangle_gltf(), TRIANGLE_BIN, json_length=0xfffffff0)},
                                               "s.glb", 1, "GLB chunk claims"),
        "glTF nodes listing the next twice": ({"s.glb": glb(doubling, TRIANGLE_BIN)}, "s.glb", 1, "node instances"),
        "glTF buffer claiming 4 GB": ({"s.glb": glb(claiming, TRIANGLE_BIN)}, "s.glb", 1, "buffer claims"),
    }
    for label, (files, scene, expected, limit) in cases.items():
        yield label, lambda c, f=files, s=scene, e=expected, m=limit: bomb_case(c, loom, timeout, f, s, e, m)


def bomb_case(d, loom, timeout, files, scene, expected_rc, limit_text):
    """Under a 3 GB address-space limit a bomb that allocates first fails or is
    cut short by the limit; either way its message does not name Loom's limit."""
    for name, data in files.items():
        write(os.path.join(d, name), data)
    for node, output in (("LoadScene", "scene"), ("LoadMesh", "mesh")):
        if node == "LoadMesh" and scene.endswith(".obj"):
            continue
        rc, text = run_loom(loom, d, graph({"n": {"type": node, "inputs": {"path": scene}}}), timeout,
                            ["--target", "n." + output], limits={resource.RLIMIT_AS: 3 << 30})
        if rc is None:
            return "hang", rc, text
        if node == "LoadScene" and (limit_text not in text or rc != expected_rc):
            return ("memory" if limit_text not in text else "unclear"), rc, text
        if rc not in (0, 1) or "bad_alloc" in text or "out of memory" in text:
            return "memory", rc, text
    return "ok", rc, text


def family_long_name(loom, timeout):
    yield "SaveImage to a 255-byte name", lambda c: long_name_case(c, loom, timeout)


def long_name_case(d, loom, timeout):
    name = "a" * 251 + ".png"
    rc, text = run_loom(loom, d, writer_graph("SaveImage", name), timeout)
    return ("ok" if rc == 0 and os.path.exists(os.path.join(d, "out", name)) else "unclear"), rc, text


FAMILIES = {"symlink": family_symlink, "cache": family_cache, "fifo": family_fifo, "signal": family_signal,
            "full-disk": family_full_disk, "scene-bomb": family_scene_bomb, "long-name": family_long_name}


def environment_cases(loom, timeout, only_families=None):
    """(family, label, run) triples; run(folder) returns (verdict, exit code, output)."""
    for family, make in FAMILIES.items():
        if only_families and family not in only_families:
            continue
        for label, run in make(loom, timeout):
            yield family, label, run


def run_environment_case(keep_dir, case):
    family, label, run = case
    d = tempfile.mkdtemp(prefix="probe-env-", dir=keep_dir)
    start = time.monotonic()
    try:
        verdict, rc, text = run(d)
    except Exception as e:  # the probe's own setup failing is reported, not hidden
        verdict, rc, text = "probe-error", None, repr(e)
    last = [l for l in text.strip().splitlines() if l.strip()]
    return {"node": family, "case": label, "verdict": verdict, "exit": rc,
            "seconds": round(time.monotonic() - start, 2), "graph": os.path.join(d, "g.json"),
            "last_line": (last[-1] if last else "")[:200]}
