"""What the tests of tests/process share: they watch `loom` from outside with
strace, which a sanitized build would mislead (its runtime has a malloc and
threads of its own)."""
import shutil
import subprocess


def unavailable(program, sanitizer_effect):
    """Why `program` cannot be checked here, or None."""
    if not shutil.which("strace"):
        return "strace is not installed"
    linked = subprocess.run(["ldd", program], capture_output=True, text=True).stdout
    if "libasan" in linked or "libtsan" in linked:
        return f"{program} is built with a sanitizer, {sanitizer_effect}"
    return None
