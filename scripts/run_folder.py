"""The output folder of a ringdem run, as the figure and check scripts take it on their command
line: argparse types that refuse a path that is not one with a message, instead of a traceback
from the first file the script opens."""

import argparse
import os


def folder_with(*files):
    """An argparse type: a folder that holds every one of FILES."""

    def check(text):
        if not os.path.isdir(text):
            raise argparse.ArgumentTypeError(f"{text}: no such folder (give a run's output folder)")
        missing = [f for f in files if not os.path.isfile(os.path.join(text, f))]
        if missing:
            why = (" (a run writes summary.json when it ends; a stopped run, after its --restart)"
                   if "summary.json" in missing else "")
            raise argparse.ArgumentTypeError(
                f"{text}: not a run's output folder, it lacks {' and '.join(missing)}{why}")
        return text

    return check


# A finished run's folder: what the rockfall and debris scripts read.
run_folder = folder_with("summary.json", "series.csv")
