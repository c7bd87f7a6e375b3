"""python/README.md's install on Debian, run as written (CTest python_pip_venv):

1. `/usr/bin/python3 -m pip install ...` without a venv is refused (PEP 668), where Debian marks the
   interpreter externally managed;
2. `python3 -m venv --system-site-packages --without-pip VENV` (Debian's pip, seen through the system
   site packages, installs into the venv; a venv with its own pip takes ~20 s more to make), then `VENV/bin/python -m pip install
   --no-build-isolation --no-index --no-deps python/` with RAYPROOF_CMAKE_BUILD_DIR set to the build
   tree, which reuses the module CTest already built rather than compiling every library again;
3. the module imports from the venv and casts a mesh read by rayproof.load_mesh.

The pip source is a copy of python/setup.py and python/pyproject.toml in a scratch directory, so that
setuptools' build/ and egg-info/ land there and not in the source tree. Exit 77 (CTest: skipped)
with a message where python3-venv or pip is missing.

Usage: pip_venv.py PYTHON SOURCE_DIR BUILD_DIR"""
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time

SKIP = 77


def run(cmd, env, **kw):
    print("+", " ".join(map(str, cmd)), flush=True)
    return subprocess.run(list(map(str, cmd)), env=env, capture_output=True, text=True, **kw)


def main():
    python, source, build = sys.argv[1], pathlib.Path(sys.argv[2]), pathlib.Path(sys.argv[3])
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV", "PIP_USER")}
    start = time.monotonic()
    probe = run([python, "-c", "import venv, ensurepip, pip"], env)
    if probe.returncode != 0:
        print(f"SKIP: {python} lacks venv, ensurepip or pip (Debian: python3-venv python3-pip): "
              f"{probe.stderr.strip().splitlines()[-1:]}")
        return SKIP

    # 1. Without a venv, Debian's interpreter refuses (PEP 668), as python/README.md says.
    stdlib = pathlib.Path(run([python, "-c", "import sysconfig; print(sysconfig.get_path('stdlib'))"], env).stdout.strip())
    if (stdlib / "EXTERNALLY-MANAGED").exists():
        r = run([python, "-m", "pip", "install", "--no-build-isolation", "--no-index", "--no-deps",
                 source / "python"], env)
        if r.returncode == 0 or "externally-managed-environment" not in r.stdout + r.stderr:
            print("FAIL: pip without a venv was expected to stop with externally-managed-environment:\n",
                  r.stdout[-2000:], r.stderr[-2000:])
            return 1
        print("pip without a venv: refused (externally-managed-environment), as documented")
    else:
        print(f"note: {stdlib}/EXTERNALLY-MANAGED is absent here: the PEP 668 refusal is not checked")

    with tempfile.TemporaryDirectory(prefix="rayproof_pip_") as scratch:
        scratch = pathlib.Path(scratch)
        venv = scratch / "venv"
        t0 = time.monotonic()
        r = run([python, "-m", "venv", "--system-site-packages", "--without-pip", venv], env)
        if r.returncode != 0:
            print(f"SKIP: {python} -m venv failed (Debian: python3-venv): {r.stderr.strip()[-500:]}")
            return SKIP
        t_venv = time.monotonic() - t0
        vpy = venv / "bin" / "python"
        pkg = scratch / "python"
        pkg.mkdir()
        for f in ("setup.py", "pyproject.toml"):
            shutil.copy2(source / "python" / f, pkg / f)
        t0 = time.monotonic()
        r = run([vpy, "-m", "pip", "install", "--no-build-isolation", "--no-index", "--no-deps", pkg],
                dict(env, RAYPROOF_CMAKE_BUILD_DIR=str(build)), cwd=scratch)
        t_pip = time.monotonic() - t0
        if r.returncode != 0:
            print("FAIL: pip install in the venv:\n", r.stdout[-3000:], r.stderr[-3000:])
            return 1
        print(f"venv {t_venv:.1f} s, pip install {t_pip:.1f} s")

        # 3. The venv's module, not the build tree's, reads a mesh and casts into it.
        mesh = scratch / "tet.off"
        mesh.write_text("OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n")
        code = f"""
import pathlib, numpy as np, rayproof
site = pathlib.Path(rayproof.__file__).resolve()
assert pathlib.Path({str(venv)!r}).resolve() in site.parents, site
v, i = rayproof.load_mesh({str(mesh)!r})
assert v.shape == (4, 3) and i.shape == (4, 3) and i.dtype == np.uint32
h = rayproof.Mesh(v, i).closest(np.array([[2.0, 0.2, 0.2]]), np.array([[-1.0, 0, 0]]))
assert h["hit"][0] and abs(h["t"][0] - 1.4) < 1e-6, h  # robust computes in float
print("imported from", site)
"""
        r = run([vpy, "-c", code], env, cwd=scratch)
        if r.returncode != 0:
            print("FAIL: the installed module:\n", r.stdout[-2000:], r.stderr[-2000:])
            return 1
        print(r.stdout.strip())
    print(f"python_pip_venv: {time.monotonic() - start:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
