// SPDX-License-Identifier: MIT
// A Flamenco 3 job type: a ddof frame sequence in chunks of frames, one `ddof` run per task.
// Copy this file into the Manager's `scripts/` folder and restart the Manager (docs/farm.md).
// Each task runs ddof with --skip-existing (a re-queued task does not recompute the frames a
// stopped one finished) and its own --stats file; `ddof-farm report STATS_DIR` merges them.
// Checked with `node --check` only: not run against a Manager (docs/farm.md).

const JOB_TYPE = {
    label: "ddof Depth of Field",
    description: "Diffusion depth of field (ddof) on a rendered EXR sequence",
    settings: [
        { key: "ddof", type: "string", default: "ddof", required: true,
          description: "The ddof command on the Workers (a path, or the name on their PATH)" },
        { key: "arguments", type: "string", required: true,
          description: "ddof's arguments with absolute paths, e.g. /shots/a/render_####.exr -o /shots/a/dof/dof_####.exr --camera /shots/a/camera.json" },
        { key: "frames", type: "string", required: true,
          eval: "f'{C.scene.frame_start}-{C.scene.frame_end}'",
          description: "Frames, as ddof --frames reads them (1-240, 1-240x2, 1,4,10-12)" },
        { key: "chunk_size", type: "int32", default: 10, required: true,
          description: "Frames per task" },
        { key: "stats_dir", type: "string", subtype: "dir_path", required: true,
          description: "Where each task writes its --stats file" },
    ],
};

// ddof's arguments as words: split on white space, with "double quotes" around a word that
// holds spaces.
function splitArguments(text) {
    const words = [];
    const re = /"([^"]*)"|(\S+)/g;
    let m;
    while ((m = re.exec(text)) !== null)
        words.push(m[1] !== undefined ? m[1] : m[2]);
    return words;
}

// The options each task sets itself (ddof also reads them as --name=value).
const FARM_OPTIONS = ["--frames", "--stats", "--skip-existing"];

// FNV-1a, 32 bits, of a chunk's text (ASCII: digits, ',' and '-'), as 8 hex digits.
function fnv1a32(text) {
    let h = 0x811c9dc5;
    for (let i = 0; i < text.length; i++)
        h = Math.imul(h ^ text.charCodeAt(i), 0x01000193) >>> 0;
    return h.toString(16).padStart(8, "0");
}

// A short name unique to a chunk, for its --stats file: the chunk itself when it is one frame
// or one run, else its first and last frames and a hash of it (frames on twos would otherwise
// make a name longer than a file name may be). As ddof_farm/frames.py chunk_name.
function chunkName(chunk) {
    if (!chunk.includes(","))
        return chunk;
    const parts = chunk.split(",");
    const first = parts[0].split("-")[0];
    const lastRun = parts[parts.length - 1].split("-");
    return `${first}-${lastRun[lastRun.length - 1]}_${fnv1a32(chunk)}`;
}

function compileJob(job) {
    const settings = job.settings;
    const args = splitArguments(settings.arguments);
    for (const arg of args)
        for (const option of FARM_OPTIONS)
            if (arg === option || arg.startsWith(option + "="))
                throw new Error(`${option} is the job's to set per task; leave it out of ddof's arguments`);
    for (const chunk of frameChunker(settings.frames, settings.chunk_size)) {
        const task = author.Task(`ddof-${chunk}`, "misc");
        task.addCommand(author.Command("exec", {
            exe: settings.ddof,
            args: args.concat(["--frames", chunk, "--skip-existing", "--stats",
                               path.join(settings.stats_dir, `chunk_${chunkName(chunk)}.json`)]),
        }));
        job.addTask(task);
    }
}
