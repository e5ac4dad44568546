"""The child-process measurement the benchmarks share: a command run in a
fresh Python child, so that the child's max RSS is the command's own."""
import json
import subprocess
import sys

# The child: runs its arguments as a command and prints, as JSON, the exit
# code, the wall-clock seconds, the max RSS (KiB) and the ends of the output.
CHILD = (
    "import resource,subprocess,sys,time,json\n"
    "t=time.perf_counter()\n"
    "p=subprocess.run(sys.argv[2:],capture_output=True,text=True)\n"
    "dt=time.perf_counter()-t\n"
    "keep=int(sys.argv[1])\n"
    "print(json.dumps({'rc':p.returncode,'s':dt,'kb':resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss,"
    "'out':p.stdout[-keep:],'err':p.stderr[-keep:]}))\n"
)


def run_child(cmd, cwd, env, keep):
    """Runs cmd in a fresh Python child. Returns a dict: rc (exit code),
    s (wall-clock seconds), gib (max RSS in GiB), out and err (the last
    `keep` characters of each)."""
    p = subprocess.run([sys.executable, "-c", CHILD, str(keep)] + cmd, cwd=cwd, env=env, capture_output=True, text=True)
    r = json.loads(p.stdout)
    r["gib"] = r.pop("kb") / 1024.0 / 1024.0
    return r
