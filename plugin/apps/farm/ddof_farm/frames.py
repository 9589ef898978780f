# SPDX-License-Identifier: MIT
"""Frame lists as `ddof --frames` writes them ("1-24", "1-24x2", "1,4,10-12") and their chunks."""


# ddof's own bounds (plugin/apps/cli/frames.h): a list ddof would refuse is refused here, when
# the job is made, rather than in every task; counting before expanding also keeps a typo such
# as 1-99999999 from filling the memory.
FRAMES_MAX = 1000000
FRAMES_LARGEST = 99999999


class FrameError(ValueError):
    """A frame list that cannot be read."""


def parse(spec):
    """The frames of a --frames list, in order, each once."""
    frames = []
    seen = set()
    count = 0
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
        count += (end - start) // step + 1
        if count > FRAMES_MAX:
            raise FrameError("the frame list %r holds more than %d frames" % (spec, FRAMES_MAX))
        for frame in range(start, end + 1, step):
            if frame not in seen:
                seen.add(frame)
                frames.append(frame)
    return frames


def _number(text, spec):
    # Digits only, as ddof reads them (int() would also take "+5", " 5" and "1_000").
    if not (text.isascii() and text.isdigit()):
        raise FrameError("%r in the frame list %r is not a frame number" % (text, spec))
    value = int(text)
    if value > FRAMES_LARGEST:
        raise FrameError("%d in %r: frame numbers (and steps) are at most %d, as in ddof"
                         % (value, spec, FRAMES_LARGEST))
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


def chunk_name(chunk):
    """A short name unique to a chunk (a --frames list), for its file names: the list itself
    when it is one frame or one run (at most 17 characters), else its first and last frames
    and a hash of the list (a chunk of frames on twos would otherwise make a name longer than a
    file name may be). ddof.js (Flamenco) names chunks the same way."""
    if "," not in chunk:
        return chunk
    first = chunk.split(",")[0].split("-")[0]
    last = chunk.split(",")[-1].split("-")[-1]
    return "%s-%s_%08x" % (first, last, fnv1a32(chunk))


def fnv1a32(text):
    """FNV-1a, 32 bits, of text's UTF-8 bytes (simple enough to write again in JavaScript)."""
    h = 0x811C9DC5
    for byte in text.encode("utf-8"):
        h = ((h ^ byte) * 0x01000193) & 0xFFFFFFFF
    return h


def chunks(frames, size):
    """The frames in chunks of `size` (the last may be shorter), each a --frames list."""
    if size < 1:
        raise FrameError("the chunk size must be at least 1, not %d" % size)
    frames = list(frames)
    return [format_frames(frames[i:i + size]) for i in range(0, len(frames), size)]
