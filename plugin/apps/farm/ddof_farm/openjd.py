# SPDX-License-Identifier: MIT
"""The job as an Open Job Description template (specification jobtemplate-2023-09): one step
whose task parameter is the chunk (a ddof --frames list), each task one `ddof` run from the
job's directory. `openjd check` validates it and `openjd run` runs it (openjd-cli); Deadline
Cloud and other OpenJD schedulers take the same file."""

import json

from . import frames as frame_lists
from .job import JobError


# jobtemplate-2023-09: a task parameter's range lists at most 1024 values.
MAX_TASKS = 1024


class _Literals:
    """The template's strings are OpenJD format strings, where "{{...}}" is replaced: a string
    of the user's that holds "{{" goes in as a job parameter whose default is the string
    (parameter values are not read again), the template naming the parameter in its place."""

    def __init__(self):
        self.parameters = []

    def __call__(self, text):
        if "{{" not in text:
            return text
        if len(text) > 1024:
            raise JobError("%r holds {{ and is longer than the 1024 characters an OpenJD job "
                           "parameter can hold" % text[:60])
        name = "Literal%d" % (len(self.parameters) + 1)
        self.parameters.append({"name": name, "type": "STRING", "default": text})
        return "{{Param.%s}}" % name


def template(job):
    """The template as a dict (JSON-serialisable)."""
    if len(job.chunks) > MAX_TASKS:
        raise JobError("%d tasks: an OpenJD step's task parameter holds at most %d values; "
                       "use a larger --chunk" % (len(job.chunks), MAX_TASKS))
    literal = _Literals()
    # POSIX sh changes to the job's directory, then execs ddof with its arguments: OpenJD runs
    # actions in a session directory of its own, and ddof's relative paths mean the job's. The
    # arguments stay separate words throughout: sh reads only its own fixed script.
    run = ["-c", 'cd "$1" && shift && exec "$@"', "ddof-chunk", literal(job.workdir),
           literal(job.ddof)]
    run += [literal(a) for a in job.ddof_args]
    run += ["--frames", "{{Task.Param.Frames}}", "--skip-existing", "--stats",
            literal(job.stats_dir + "/chunk_") + "{{Task.Param.Chunk}}.json"]
    name = literal(job.name)
    result = {
        "specificationVersion": "jobtemplate-2023-09",
        "name": name,
        "steps": [{
            "name": "ddof",
            "parameterSpace": {
                # Each task's frames and the short name of its --stats file, taken in pairs.
                "taskParameterDefinitions": [
                    {"name": "Frames", "type": "STRING", "range": job.chunks},
                    {"name": "Chunk", "type": "STRING",
                     "range": [frame_lists.chunk_name(c) for c in job.chunks]},
                ],
                "combination": "(Frames, Chunk)",
            },
            "script": {
                "actions": {"onRun": {"command": "/bin/sh", "args": run}},
            },
        }],
    }
    if literal.parameters:
        result["parameterDefinitions"] = literal.parameters
    return result


def write(job, path):
    import os
    os.makedirs(job.stats_dir, exist_ok=True)
    with open(path, "w", encoding="utf-8") as f:
        json.dump(template(job), f, indent=2)
        f.write("\n")
