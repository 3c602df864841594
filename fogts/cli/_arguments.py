"""Library argument names in an error message, as the options the user typed.

The library's errors name its arguments (``fs_hz``, ``nan='drop'``); the command line's
error guard (:func:`fogts.cli._common.guard`) passes each message through
:func:`option_names`, so that the same error names ``--fs`` or ``--nan drop`` there.  One
table for the options every command shares, one mapping per command for its own.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping

__all__ = ["ARGUMENT_OPTIONS", "option_names"]

#: The library keywords whose option is the same in every command (the shared input
#: options, and those a library error suggests): the library's messages name the keyword
#: (``pass fs_hz=``, ``nan='drop'``, ``give n_samples=N``), and :func:`option_names` turns
#: it into the option on the command line (``pass --fs``, ``--nan drop``,
#: ``give --n-samples N``).
ARGUMENT_OPTIONS: dict[str, str] = {
    "fs_hz": "--fs", "rate_column": "--rate-column", "time_column": "--time-column",
    "temperature_column": "--temperature-column", "topic": "--topic", "input": "--input",
    "nan": "--nan", "gaps": "--gaps", "n_samples": "--n-samples", "taus": "--taus",
    "terms": "--terms", "channel": "--channel",
}


def option_names(message: str, options: Mapping[str, str]) -> str:
    """Name in ``message`` the options the user typed instead of the library's arguments.

    A keyword as the library's errors suggest it, ``name=`` with an optional value (quoted
    or a word: ``fs_hz=``, ``nan='drop'``, ``n_samples=N``), becomes the option with that
    value (``--fs``, ``--nan drop``, ``--n-samples N``), for the names of
    :data:`ARGUMENT_OPTIONS` and of ``options``; the names of ``options`` (the command's
    own, e.g. ``{"latitude_deg": "--latitude"}``) are also replaced where they stand as
    whole words.

    Examples
    --------
    >>> option_names("pass fs_hz= or add a time column", {})
    'pass --fs or add a time column'
    >>> option_names("pass nan='drop' or nan='interpolate'", {})
    'pass --nan drop or --nan interpolate'
    >>> option_names("latitude_deg = 95 is not a latitude", {"latitude_deg": "--latitude"})
    '--latitude = 95 is not a latitude'
    >>> option_names("give n_samples=N.", {})
    'give --n-samples N.'
    """
    def keyword(option: str) -> Callable[[re.Match[str]], str]:
        def sub(match: re.Match[str]) -> str:
            value = match.group(1) if match.group(1) is not None else match.group(2)
            return f"{option} {value}" if value else option
        return sub

    for name, option in {**ARGUMENT_OPTIONS, **options}.items():
        message = re.sub(rf"(?<![\w.-]){re.escape(name)}=(?!\.\.\.|[(\[{{])"
                         r"(?:'([^']*)'|(\w(?:[\w./|-]*\w)?))?", keyword(option), message)
    for name, option in options.items():
        message = re.sub(rf"(?<![\w-]){re.escape(name)}(?!\w)", option, message)
    return message
