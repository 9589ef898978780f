# SPDX-License-Identifier: MIT
"""Frame lists as `ddof --frames` writes them ("1-24", "1-24x2", "1,4,10-12") and their chunks."""


class FrameError(ValueError):
    """A frame list that cannot be read."""


def parse(spec):
    """The frames of a --frames list, in order, each once."""
    frames = []
    seen = set()
    for part in str(spec).split(","):
        part = part.strip()
        if not part:
            raise FrameError("empty item in the frame list %r" % spec)
        step = 1
        if "x" in part:
            part, _, step_text = part.partition("x")
            step = _number(step_text, spec)
            if step < 1:
                raise FrameError("step %d in %r must be at least 1" % (step, spec))
        first, sep, last = part.partition("-")
        start = _number(first, spec)
        end = _number(last, spec) if sep else start
        if end < start:
            raise FrameError("range %s in %r runs backwards" % (part, spec))
        for frame in range(start, end + 1, step):
            if frame not in seen:
                seen.add(frame)
                frames.append(frame)
    return frames


def _number(text, spec):
    try:
        value = int(text)
    except ValueError:
        raise FrameError("%r in the frame list %r is not a frame number" % (text, spec)) from None
    if value < 0:
        raise FrameError("frame %d in %r is negative" % (value, spec))
    return value


def format_frames(frames):
    """The shortest ddof --frames list of these frames: runs of consecutive frames as A-B."""
    parts = []
    frames = list(frames)
    i = 0
    while i < len(frames):
        j = i
        while j + 1 < len(frames) and frames[j + 1] == frames[j] + 1:
            j += 1
        parts.append(str(frames[i]) if i == j else "%d-%d" % (frames[i], frames[j]))
        i = j + 1
    return ",".join(parts)


def chunks(frames, size):
    """The frames in chunks of `size` (the last may be shorter), each a --frames list."""
    if size < 1:
        raise FrameError("the chunk size must be at least 1, not %d" % size)
    frames = list(frames)
    return [format_frames(frames[i:i + size]) for i in range(0, len(frames), size)]
