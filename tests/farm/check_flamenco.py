# SPDX-License-Identifier: MIT
"""The Flamenco job type (plugin/apps/farm/ddof_farm/flamenco/ddof.js) is valid JavaScript that
defines JOB_TYPE and compileJob; and compileJob, run by Node with stand-ins for Flamenco's
author/frameChunker/path, makes one exec task per chunk with --frames, --skip-existing and
--stats. Flamenco itself is not installable here: this is all that is checked."""
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
"""
out = subprocess.run([node, "-e", harness], capture_output=True, text=True)
print(out.stdout, out.stderr)
want = ('[["ddof-1-5","exec",{"exe":"ddof","args":["/a b/r_####.exr","-o","/o/d_####.exr","-q",'
        '"--frames","1-5","--skip-existing","--stats","/s/chunk_1-5.json"]}]')
ok = out.returncode == 0 and out.stdout.startswith(want) and '"ddof-11-12"' in out.stdout
print("ok" if ok else "FAILED: compileJob's tasks")
sys.exit(0 if ok else 1)
