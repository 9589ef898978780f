# SPDX-License-Identifier: MIT
"""ddof on render farms: one `ddof` frame sequence as a farm job (OpenCue, Open Job Description,
Flamenco), cut into chunks of frames, and the chunks' --stats files merged into one report.
Plain Python; pyoutline (OpenCue) and openjd are imported only by the engines that need them."""

__version__ = "0.8.0"
