# SPDX-License-Identifier: MIT
"""The job as an Open Job Description template (specification jobtemplate-2023-09): one step
whose task parameter is the chunk (a ddof --frames list), each task one `ddof` run from the
job's directory. `openjd check` validates it and `openjd run` runs it (openjd-cli); Deadline
Cloud and other OpenJD schedulers take the same file."""

import json


def template(job):
    """The template as a dict (JSON-serialisable)."""
    # POSIX sh changes to the job's directory, then execs ddof with its arguments: OpenJD runs
    # actions in a session directory of its own, and ddof's relative paths mean the job's.
    run = ["-c", 'cd "$1" && shift && exec "$@"', "ddof-chunk", job.workdir, job.ddof]
    run += job.ddof_args + ["--frames", "{{Task.Param.Frames}}", "--skip-existing", "--stats",
                            job.stats_dir + "/chunk_{{Task.Param.Frames}}.json"]
    return {
        "specificationVersion": "jobtemplate-2023-09",
        "name": job.name,
        "steps": [{
            "name": "ddof",
            "parameterSpace": {
                "taskParameterDefinitions": [{
                    "name": "Frames",
                    "type": "STRING",
                    "range": job.chunks,
                }],
            },
            "script": {
                "actions": {"onRun": {"command": "/bin/sh", "args": run}},
            },
        }],
    }


def write(job, path):
    import os
    os.makedirs(job.stats_dir, exist_ok=True)
    with open(path, "w", encoding="utf-8") as f:
        json.dump(template(job), f, indent=2)
        f.write("\n")
