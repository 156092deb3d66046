"""`rosrun kane_sim identify`: its command line, checked before any heavy import, and its stages
(the excitation table, the fit, the fitted config and the plot) around kane_sim.identify. Imports
only the standard library until the arguments are checked, so that a typo costs no NumPy and
Ctrl-C during the imports is an exit 130, not a traceback (scripts/identify is this, run)."""
import argparse
import math
import os
import signal
import sys


# A row of --excite's table is at most this long ("3600.000000,-12.3456789012\n"); the file
# stays below simulate's --torque-csv limit (64 MiB) with room to spare.
EXCITE_ROW_BYTES = 30
EXCITE_MAX_BYTES = 60e6


def _bandwidth(text):
    if text == "auto":
        return "auto"
    if text == "none":
        return None
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError("--bandwidth takes a number of Hz, auto or none, got %r"
                                         % text) from None
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError("--bandwidth must be a positive number of Hz, got %r"
                                         % text)
    return value


def _fraction(text):
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError("--holdout takes a fraction, got %r" % text) from None
    if not 0 <= value < 0.9:
        raise argparse.ArgumentTypeError("--holdout must be in [0, 0.9), got %r" % text)
    return value


def _duration(text):
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError("--excite takes a duration in seconds, got %r"
                                         % text) from None
    if not (math.isfinite(value) and 2 <= value <= 3600):
        raise argparse.ArgumentTypeError("--excite duration must be in [2, 3600] s, got %r" % text)
    return value


def _seed(text):
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError("--seed takes a whole number, got %r" % text) from None
    if value < 0:
        raise argparse.ArgumentTypeError("--seed must be 0 or more, got %r" % text)
    return value


def _writable(parser, flag, path):
    """Refuses before any work an output that cannot be written: a folder, a missing folder."""
    if os.path.isdir(path):
        parser.error("%s %s is a folder: give a file name" % (flag, path))
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        parser.error("%s %s: the folder %s does not exist" % (flag, path, folder))
    if not os.access(folder, os.W_OK) or (os.path.exists(path) and not os.access(path, os.W_OK)):
        parser.error("%s %s cannot be written (permissions)" % (flag, path))


# A controller's gains file is a few lines; anything larger is not one.
CONTROLLER_MAX_BYTES = 1 << 20


def _readable(parser, flag, path):
    """parser.error unless `path` is a regular file of at most CONTROLLER_MAX_BYTES (a device
    such as /dev/zero would be read forever)."""
    if not os.path.isfile(path):
        parser.error("%s %s is not a readable file (%s)" % (
            flag, path, "no such file" if not os.path.exists(path) else
            "not a regular file: a device, a pipe or a folder"))
    if os.path.getsize(path) > CONTROLLER_MAX_BYTES:
        parser.error("%s %s is %d bytes: a controller's gains file is a few lines"
                     % (flag, path, os.path.getsize(path)))


def _controller_gains(path):
    """The controller's parameters from its YAML file (ValueError naming the file)."""
    import yaml
    try:
        with open(path, encoding="utf-8") as f:
            return yaml.safe_load(f)
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as e:
        raise ValueError("not YAML: %s" % " ".join(str(e).split())) from None


def _write(path, *parts):
    """Writes the texts (or iterables of texts: written as they come) to path; exit 4 if not."""
    try:
        with open(path, "w") as f:
            for part in parts:
                f.writelines([part] if isinstance(part, str) else part)
    except OSError as e:
        print("identify: cannot write %s: %s" % (path, e.strerror), file=sys.stderr)
        sys.exit(4)


def _offset_note(fit):
    """The fitted torque offset, which no config key holds, as a sentence; None if not fitted."""
    if "torque_offset" not in fit.estimates or "torque_offset" in fit.kept:
        return None
    return ("torque_offset %.4g +- %.2g N m is not written (no config key): the rig delivered that "
            "much more than its effort reads; add it to the torque you command"
            % (fit.estimates["torque_offset"], fit.std_errors["torque_offset"]))


def _parser(description):
    parser = argparse.ArgumentParser(description=description, allow_abbrev=False)
    parser.add_argument("data", nargs="?", help="a bag with joint_states, or a simulate CSV")
    parser.add_argument("--config", help="the base config (default: the package's mechanism.yaml)")
    parser.add_argument("-o", "--output",
                        help="the fitted config (or with --excite the torque or setpoint CSV)")
    parser.add_argument("--params", help="comma-separated names to identify (--list shows them)")
    parser.add_argument("--method", default="energy", choices=("energy", "equations"))
    parser.add_argument("--bandwidth", type=_bandwidth, default="auto",
                        help="the derivative filter's Hz, auto (default) or none")
    parser.add_argument("--holdout", type=_fraction, default=0.25,
                        help="the last fraction of the data held out for cross-validation")
    parser.add_argument("--topic", help="the JointState topic of a bag (default: *joint_states)")
    parser.add_argument("--plot", help="PNG: recorded q1, q2 against the fitted and base models")
    parser.add_argument("--no-validate", action="store_true",
                        help="skip re-simulating the recorded torque")
    parser.add_argument("--force", action="store_true",
                        help="write the fit even when it is refused (its reason still printed)")
    parser.add_argument("--no-refine", action="store_true",
                        help="least squares only: skip the output-error fit on measured data")
    parser.add_argument("--excite", type=_duration, metavar="DURATION",
                        help="write an exciting torque (a servo base: setpoint) profile of this "
                        "many seconds to -o")
    parser.add_argument("--seed", type=_seed, default=0, help="--excite's phase draw")
    parser.add_argument("--controller", metavar="GAINS.yaml",
                        help="--excite for the example PD controller with these gains "
                        "(config/controller.yaml): writes its setpoint table, for "
                        "pd_controller _setpoint_table:=")
    parser.add_argument("--list", action="store_true", help="list the identifiable parameters")
    return parser


def _check(parser, args):
    """parser.error (exit 2) for arguments that contradict each other or outputs that would
    overwrite the data, each other, or cannot be written, before any work."""
    outputs = [("-o", args.output), ("--plot", args.plot)]
    for flag, path in outputs:
        if path is not None and path == "":
            parser.error("%s needs a file name, got ''" % flag)
        if path and args.data and os.path.exists(args.data) and os.path.exists(path) and \
                os.path.samefile(path, args.data):
            parser.error("%s %s is the DATA file: it would be overwritten" % (flag, path))
    if args.output and args.plot and os.path.abspath(args.output) == os.path.abspath(args.plot):
        parser.error("-o and --plot name the same file %s" % args.output)
    if args.plot and not args.plot.lower().endswith(".png"):
        parser.error("--plot writes a PNG: give a name ending in .png, got %s" % args.plot)
    for flag, path in outputs:
        if path:
            _writable(parser, flag, path)
    if args.list and (args.data or args.output or args.excite is not None):
        parser.error("--list takes no DATA, -o or --excite")
    if args.force and (args.list or args.excite is not None):
        parser.error("--force is for a fit (it writes one that was refused), not --list or "
                     "--excite")
    if args.params is not None and not args.params.strip(" ,"):
        parser.error("--params needs names (--list shows them), got %r" % args.params)
    if args.excite is not None and (args.data or not args.output):
        parser.error("--excite takes no DATA and needs -o TORQUE.csv")
    if args.controller is not None and args.excite is None:
        parser.error("--controller is for --excite (the controller's setpoint table)")
    if args.controller is not None:
        _readable(parser, "--controller", args.controller)
        if args.output and os.path.exists(args.output) and \
                os.path.samefile(args.output, args.controller):
            parser.error("-o %s is the --controller file: it would be overwritten" % args.output)
    if args.excite is None and not args.list and not args.data:
        parser.error("DATA is required (or --excite, --list)")


def _write_excitation(args, base, ki):
    """--excite: the profile's table at the highest of 1000, 500, 250 and 100 Hz that keeps it
    below simulate's 64 MiB --torque-csv limit (an hour: 250 Hz, ~25 MB; the multisine reaches
    4 Hz, so even 100 Hz holds every component)."""
    rate = next(r for r in (1000.0, 500.0, 250.0, 100.0)
                if args.excite * r * EXCITE_ROW_BYTES <= EXCITE_MAX_BYTES or r == 100.0)
    if args.controller:
        from kane_sim import ConfigError
        try:
            base = ki.pd_controller_base(base, _controller_gains(args.controller))
        except ValueError as e:  # the controller's config: exit 1, as a bad --config
            raise ConfigError("--controller %s: %s" % (args.controller, e)) from None
    t, drive, cond = ki.excitation(base, args.excite, seed=args.seed, rate=rate)
    mode = base["command.mode"]
    what, unit = ("torque", "N m") if mode == "effort" else \
        ("setpoint", "rad" if mode == "position" else "rad/s")
    _write(args.output, "t,%s\n" % what, ("%.6f,%.12g\n" % row for row in zip(t, drive)))
    play = "" if mode == "effort" else \
        " (the %s servo's setpoint: play it in command.mode %s)" % (mode, mode)
    if args.controller:
        play = " (the PD controller's setpoint: rosrun kane_sim pd_controller _setpoint_table:=%s" \
               " with the gains of %s)" % (os.path.abspath(args.output), args.controller)
    print("identify: wrote %s: %.3g s at %g Hz, |%s| <= %.4g %s, condition number %.3g on the "
          "base%s" % (args.output, args.excite, rate, what, max(abs(drive)), unit, cond, play))


def _fit(args, base, ki):
    params = [p.strip() for p in args.params.split(",")] if args.params else None
    return ki.identify(args.data, base, params=params, method=args.method,
                       bandwidth=args.bandwidth, holdout=args.holdout, topic=args.topic,
                       validate=not args.no_validate or bool(args.plot),
                       refine=False if args.no_refine else "auto",
                       progress=lambda text: print("identify: " + text, file=sys.stderr,
                                                   flush=True))


def _write_fit(args, fit):
    """The report, then (unless refused without --force) the fitted config and the plot; the
    exit code."""
    print(fit.report())  # a refusal is its REFUSED line, as Python's fit.report() says it
    refusal = fit.refusal
    if refusal and not args.force:
        print("identify: %s; nothing written (--force writes it anyway)" % refusal,
              file=sys.stderr)
        return 3
    if refusal:
        print("identify: --force: writing a refused fit: %s" % refusal, file=sys.stderr)
    if args.output:
        header = "# fitted by kane_sim identify from %s\n" % os.path.basename(args.data)
        offset = _offset_note(fit)
        if offset:
            header += "# %s\n" % offset
        if refusal:  # --force: whoever loads the file sees what it is
            header += "# REFUSED, written with --force: %s\n" % " ".join(refusal.split())
        _write(args.output, header, fit.config.yaml())
        print("identify: wrote %s%s" % (args.output, "; " + offset if offset else ""))
    if args.plot:
        from kane_sim.plotting import plot_identification
        try:
            plot_identification(fit, args.plot, title=os.path.basename(args.data))
        except OSError as e:
            print("identify: cannot write %s: %s" % (args.plot, e.strerror), file=sys.stderr)
            return 4
        except KeyboardInterrupt:
            print("identify: interrupted while plotting", file=sys.stderr)
            return 130
        print("identify: wrote %s" % args.plot)
    return 0


def _heavy_imports():
    """(kane_sim, kane_sim.identify), or None when Ctrl-C came during them: NumPy's, SciPy's
    and the module's imports must not be cut by it (a traceback, exit 1), so the signal is held
    until they are done, then delivered here."""
    signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        import kane_sim
        from kane_sim import identify as ki
    finally:
        try:
            signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
        except KeyboardInterrupt:
            return None
    return kane_sim, ki


def main(description):
    """The whole command; its exit code (0 fitted, 1 bad config, 2 bad arguments, 3 bad data
    or a refused fit, 4 a file not written, 130 interrupted)."""
    parser = _parser(description)
    args = parser.parse_args()
    signal.signal(signal.SIGINT, signal.default_int_handler)
    _check(parser, args)
    modules = _heavy_imports()
    if modules is None:
        print("identify: interrupted", file=sys.stderr)
        return 130
    kane_sim, ki = modules
    try:
        if args.list:
            for p in ki.parameters():
                print("%-28s %-10s %s" % (p["name"], p["unit"],
                                          "default" if p["by_default"] else "when asked"))
            return 0
        base = kane_sim.Config(args.config)
        if args.excite is not None:
            _write_excitation(args, base, ki)
            return 0
        fit = _fit(args, base, ki)
    except kane_sim.ConfigError as e:
        print("identify: %s" % e, file=sys.stderr)
        return 1
    except (ValueError, TypeError, OverflowError) as e:
        print("identify: %s" % e, file=sys.stderr)
        return 3
    except MemoryError:
        print("identify: out of memory reading or fitting %s: cut the recording into pieces"
              % args.data, file=sys.stderr)
        return 3
    except KeyboardInterrupt:
        print("identify: interrupted", file=sys.stderr)
        return 130
    return _write_fit(args, fit)
