"""Library argument names in a message, as the options the user typed.

The library's errors, warnings and notes name its arguments (``fs_hz``, ``nan='drop'``,
``pass units=``); the command line passes each message through :func:`option_names` (the
error guard, :func:`fogts.cli._common.guard`) or :func:`option_keywords` (the warnings
and notes it prints, and those of the JSON it writes: :func:`cli_payload`), so that the
same text names ``--fs``, ``--nan drop`` or ``pass --units`` there.  One table for the
options every command shares, one mapping per command for its own.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping, Sequence
from typing import Any, Literal

__all__ = ["ARGUMENT_OPTIONS", "BARE_ARGUMENTS", "MESSAGE_KEYS", "cli_payload",
           "measurement_noise_value", "option_keywords", "option_names", "stray_arguments"]

#: The library keywords whose option is the same in every command (the shared input
#: options, and those a library error suggests): the library's messages name the keyword
#: (``pass fs_hz=``, ``nan='drop'``, ``give n_samples=N``), and :func:`option_names` turns
#: it into the option on the command line (``pass --fs``, ``--nan drop``,
#: ``give --n-samples N``).
ARGUMENT_OPTIONS: dict[str, str] = {
    "fs_hz": "--fs", "rate_column": "--rate-column", "time_column": "--time-column",
    "temperature_column": "--temperature-column", "topic": "--topic", "input": "--input",
    "nan": "--nan", "gaps": "--gaps", "n_samples": "--n-samples", "taus": "--taus",
    "terms": "--terms", "channel": "--channel", "units": "--units", "kind": "--kind",
    "outliers": "--outliers",
}

#: The keywords of :data:`ARGUMENT_OPTIONS` that :func:`option_names` also replaces where
#: they stand alone, as a check names its argument (``fs_hz must be a finite number > 0``):
#: the identifiers (``fs_hz``, ``n_samples``, ...), which are no English word; ``units``,
#: ``input`` or ``kind`` stand alone in many a sentence and are only replaced as ``name=``.
BARE_ARGUMENTS: dict[str, str] = {k: v for k, v in ARGUMENT_OPTIONS.items() if "_" in k}

#: The JSON keys whose strings are messages (a warning, a note, a message, a line of text)
#: that may suggest a library keyword: :func:`cli_payload` names the option there instead.
MESSAGE_KEYS = frozenset({"warnings", "notes", "message", "text"})


def option_keywords(message: str, options: Mapping[str, str] | None = None) -> str:
    """Name in ``message`` the options the user typed instead of the keywords the library
    suggests: ``name=`` with an optional value (quoted or a word) becomes the option with
    that value, for the names of :data:`ARGUMENT_OPTIONS` and of ``options``.  Bare words
    stay: for the warnings and notes the command line prints and writes into its JSON,
    whose other words (a column name, a quantity) are not arguments.

    Examples
    --------
    >>> option_keywords("assuming deg/h; pass units= (deg/h, deg/s, rad/s, arcsec/s)")
    'assuming deg/h; pass --units (deg/h, deg/s, rad/s, arcsec/s)'
    >>> option_keywords("gaps='split' analyses the longest regular segment")
    '--gaps split analyses the longest regular segment'
    >>> option_keywords("outliers=7: samples beyond 7 robust sigmas; units and n_samples stay")
    '--outliers 7: samples beyond 7 robust sigmas; units and n_samples stay'
    """
    def keyword(option: str) -> Callable[[re.Match[str]], str]:
        def sub(match: re.Match[str]) -> str:
            value = match.group(1) if match.group(1) is not None else match.group(2)
            return f"{option} {value}" if value else option
        return sub

    for name, option in {**ARGUMENT_OPTIONS, **(options or {})}.items():
        message = re.sub(rf"(?<![\w.-]){re.escape(name)}=(?!\.\.\.|[(\[{{])"
                         r"(?:'([^']*)'|(\w(?:[\w./|-]*\w)?))?", keyword(option), message)
    return message


def cli_payload(payload: Any, options: Mapping[str, str] | None = None) -> Any:
    """``payload`` (a command's JSON) with :func:`option_keywords` applied to the strings
    under :data:`MESSAGE_KEYS` (``data_quality.warnings``, ``notes``,
    ``plausibility.message``, ``outliers_effect.text``, at any depth), with the command's
    own ``options`` besides the shared ones; every other value, a file or column name
    included, as it was.

    Examples
    --------
    >>> cli_payload({"source": "units=x.csv", "data_quality": {"warnings": ["pass units="]}})
    {'source': 'units=x.csv', 'data_quality': {'warnings': ['pass --units']}}
    """
    def messages(value: Any) -> Any:
        if isinstance(value, str):
            return option_keywords(value, options)
        if isinstance(value, list | tuple):
            return [messages(v) for v in value]
        return cli_payload(value, options)

    if isinstance(payload, dict):
        return {k: messages(v) if k in MESSAGE_KEYS else cli_payload(v, options)
                for k, v in payload.items()}
    if isinstance(payload, list | tuple):
        return [cli_payload(v, options) for v in payload]
    return payload


def option_names(message: str, options: Mapping[str, str]) -> str:
    """Name in ``message`` the options the user typed instead of the library's arguments.

    A keyword as the library's errors suggest it, ``name=`` with an optional value (quoted
    or a word: ``fs_hz=``, ``nan='drop'``, ``n_samples=N``), becomes the option with that
    value (``--fs``, ``--nan drop``, ``--n-samples N``), for the names of
    :data:`ARGUMENT_OPTIONS` and of ``options``; the names of ``options`` (the command's
    own, e.g. ``{"latitude_deg": "--latitude"}``) and of :data:`BARE_ARGUMENTS` (the
    shared identifiers, ``fs_hz``; not inside quotes, where a column may be named so)
    are also replaced where they stand as whole words.

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
    >>> option_names("fs_hz must be a finite number > 0, got -5.0", {})
    '--fs must be a finite number > 0, got -5.0'
    """
    message = option_keywords(message, options)
    for name, option in options.items():
        message = re.sub(rf"(?<![\w-]){re.escape(name)}(?!\w)", option, message)
    for name, option in BARE_ARGUMENTS.items():
        message = re.sub(rf"(?<![\w'.-]){re.escape(name)}(?![\w'])", option, message)
    return message


def stray_arguments(ctx: Any, argv: Sequence[str], message: str) -> str:
    """``message`` (click's missing option or argument of ``ctx``'s command) led by the
    positional tokens of ``argv`` that the command's arguments do not take: click reports
    the missing option first, so that ``fogts simulate noise out.csv`` said only that
    ``--output`` is missing, never that ``out.csv`` is no argument of it.  ``message``
    unchanged when there are none, or the command line cannot be followed to the command.
    """
    start = 0
    for name in ctx.command_path.split()[1:]:
        if name not in argv[start:]:
            return message
        start = list(argv).index(name, start) + 1
    try:  # the parser gives each Argument its tokens and returns those left over
        _, rest, _ = ctx.command.make_parser(ctx).parse_args(args=list(argv[start:]))
    except Exception:  # the original usage error is the one to show
        return message
    if not rest:
        return message
    takes = [(p.metavar or p.name or "").upper() for p in ctx.command.params
             if p.param_type_name == "argument"]
    allowed = f"only {', '.join(takes)}" if takes else "no positional argument"
    return (f"unexpected argument(s) {' '.join(map(repr, rest))}: {ctx.command_path} takes "
            f"{allowed}; {message[:1].lower()}{message[1:]}")


def measurement_noise_value(text: str) -> Literal["estimate"] | float:
    """The value of ``--measurement-noise`` (``filter``, ``compensate``): ``"estimate"`` or
    a variance in (rate unit)^2 (finite, >= 0), checked before any input is read."""
    from fogts._validate import check_positive
    from fogts.errors import DataError

    if text == "estimate":
        return "estimate"
    try:
        value = float(text)
    except ValueError:
        raise DataError("--measurement-noise must be 'estimate' or a variance in "
                        f"(rate unit)^2; got {text!r}") from None
    return check_positive("--measurement-noise", value, allow_zero=True)
