# SPDX-License-Identifier: MIT
"""The Flamenco job type (plugin/apps/farm/ddof_farm/flamenco/ddof.js) is valid JavaScript that
defines JOB_TYPE and compileJob; and compileJob, run by Node with stand-ins for Flamenco's
author/frameChunker/path, makes one exec task per chunk with --frames, --skip-existing and
--stats; it refuses --frames, --stats and --skip-existing in the user's arguments; a chunk of
frames on twos gets a short --stats name (the same as ddof_farm.frames.chunk_name). Flamenco itself is not installable here: this is all that is checked."""
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
JS = os.path.join(HERE, "..", "..", "plugin", "apps", "farm", "ddof_farm", "flamenco", "ddof.js")
node = shutil.which("node") or shutil.which("nodejs")
if not node:
    print("skipped: no node (Debian's nodejs) to check the Flamenco job type with")
    sys.exit(77)
if subprocess.run([node, "--check", JS]).returncode != 0:
    sys.exit(1)
harness = open(JS, encoding="utf-8").read() + r"""
const tasks = [];
globalThis.path = { join: (...p) => p.join("/") };
globalThis.frameChunker = (frames, size) => {
    const [a, b] = frames.split("-").map(Number), out = [];
    for (let s = a; s <= b; s += size) out.push(s + "-" + Math.min(b, s + size - 1));
    return out;
};
globalThis.author = {
    Task: (name, type) => ({ name, type, commands: [], addCommand(c) { this.commands.push(c); } }),
    Command: (type, params) => ({ type, params }),
};
compileJob({ settings: { ddof: "ddof", arguments: '"/a b/r_####.exr" -o /o/d_####.exr -q',
                         frames: "1-12", chunk_size: 5, stats_dir: "/s" },
             addTask: (t) => tasks.push(t) });
console.log(JSON.stringify(tasks.map(t => [t.name, t.commands[0].type, t.commands[0].params])));
for (const bad of ["--frames 1-3", "--stats=s.json", "--skip-existing"]) {
    try {
        compileJob({ settings: { ddof: "ddof", arguments: "/r_####.exr -o /d_####.exr " + bad,
                                 frames: "1-12", chunk_size: 5, stats_dir: "/s" },
                     addTask: () => {} });
        console.log("ACCEPTED " + bad);
    } catch (e) {
        console.log("refused: " + e.message);
    }
}
console.log("NAME " + chunkName(LONG));
"""
sys.path.insert(0, os.path.join(HERE, "..", "..", "plugin", "apps", "farm"))
from ddof_farm import frames  # noqa: E402
long_chunk = frames.chunks(frames.parse("1001-1099x2"), 50)[0]
harness = harness.replace("LONG", '"%s"' % long_chunk)
out = subprocess.run([node, "-e", harness], capture_output=True, text=True)
print(out.stdout, out.stderr)
want = ('[["ddof-1-5","exec",{"exe":"ddof","args":["/a b/r_####.exr","-o","/o/d_####.exr","-q",'
        '"--frames","1-5","--skip-existing","--stats","/s/chunk_1-5.json"]}]')
ok = out.returncode == 0 and out.stdout.startswith(want) and '"ddof-11-12"' in out.stdout
print("ok" if ok else "FAILED: compileJob's tasks")
refused = out.stdout.count("refused: ") == 3 and "ACCEPTED" not in out.stdout
print("ok" if refused else "FAILED: --frames/--stats/--skip-existing in the arguments refused")
name = "NAME %s\n" % frames.chunk_name(long_chunk)
named = len(long_chunk) > 240 and name in out.stdout and len(name) < 40
print("ok" if named else "FAILED: the short --stats name of %s" % long_chunk)
sys.exit(0 if ok and refused and named else 1)
