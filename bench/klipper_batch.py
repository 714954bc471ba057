#!/usr/bin/python3
"""Klipper's klippy.py in batch mode on a G-code file, for bench/hosts_check.py: the stock
printer.cfg of a setup, the MCU dictionary built with gcc-avr, and klippy's verdict and print
time read from its log.

Klipper's batch mode lets every extrusion through: with file output, extras/heaters.py sets
can_extrude and returns from every temperature wait at once. So that a file which extrudes with
a cold nozzle fails here as it fails on the printer, klippy runs under a small heat model
(--klippy-shim, below): a heater counts as hot once a wait for it (M109/M190, TEMPERATURE_WAIT)
asked for at least its min_extrude_temp, and cold again once its target drops below that.

    /usr/bin/python3 bench/klipper_batch.py --klippy-shim KLIPPER_DIR PRINTER_CFG -i FILE ...
runs klippy under that model (what run_klipper does).
"""

import collections
import importlib.util
import logging
import os
import re
import shutil
import subprocess
import sys
import time


def run(cmd, **kw):
    return subprocess.run(cmd, capture_output=True, text=True, **kw)


# --- the heat model klippy runs under -----------------------------------------------------------


def klippy_shim(klipper_dir, argv):
    """Runs klippy.main() with argv, heaters judged by the heat model of the module docstring."""
    sys.path.insert(0, os.path.join(klipper_dir, "klippy"))
    sys.argv = ["klippy.py"] + argv
    import klippy  # noqa: E402 (the tree is only known now)

    heaters = importlib.import_module("extras.heaters")
    init, set_temp = heaters.Heater.__init__, heaters.Heater.set_temp
    wait, temp_wait = (heaters.PrinterHeaters._wait_for_temperature,
                       heaters.PrinterHeaters.cmd_TEMPERATURE_WAIT)

    def cold_or_hot(heater, hot, why):
        if heater.can_extrude != hot:
            logging.info("heat model: %s %s (%s)", heater.get_name(), "hot" if hot else "cold", why)
        heater.can_extrude = hot

    def patched_init(self, config, sensor):
        init(self, config, sensor)
        self.can_extrude = self.min_extrude_temp <= 0.

    def patched_set_temp(self, degrees):
        set_temp(self, degrees)
        if degrees < self.min_extrude_temp and self.min_extrude_temp > 0.:
            cold_or_hot(self, False, "target %.0f" % degrees)

    def patched_wait(self, heater):
        if heater.target_temp >= heater.min_extrude_temp:
            cold_or_hot(heater, True, "waited for %.0f" % heater.target_temp)
        return wait(self, heater)

    def patched_temp_wait(self, gcmd):
        heater = self.heaters.get(gcmd.get("SENSOR"))
        minimum = gcmd.get_float("MINIMUM", float("-inf"))
        if heater is not None and minimum >= heater.min_extrude_temp:
            cold_or_hot(heater, True, "TEMPERATURE_WAIT MINIMUM=%.0f" % minimum)
        return temp_wait(self, gcmd)

    heaters.Heater.__init__ = patched_init
    heaters.Heater.set_temp = patched_set_temp
    heaters.PrinterHeaters._wait_for_temperature = patched_wait
    heaters.PrinterHeaters.cmd_TEMPERATURE_WAIT = patched_temp_wait
    klippy.main()


# --- Klipper ------------------------------------------------------------------------------------


def build_dictionary(klipper, mcu, work):
    """Klipper's MCU data dictionary for an AVR, built with gcc-avr as its CI builds it."""
    out = os.path.join(work, "dict", mcu + ".dict")
    if os.path.isfile(out):
        return out, None
    if not shutil.which("avr-gcc"):
        return None, "avr-gcc not found (Debian: gcc-avr avr-libc binutils-avr)"
    os.makedirs(os.path.dirname(out), exist_ok=True)
    shutil.copy(os.path.join(klipper, "test", "configs", mcu + ".config"),
                os.path.join(klipper, ".config"))
    for step in (["make", "clean"], ["make", "olddefconfig"], ["make", "-j", "2"]):
        r = run(step, cwd=klipper)
        if r.returncode != 0:
            return None, "building Klipper for %s failed: %s" % (mcu, r.stderr.strip()[-300:])
    shutil.copy(os.path.join(klipper, "out", "klipper.dict"), out)
    return out, None


def klipper_setup(klipper, name, work):
    """A printer.cfg of stock files for one setup, and the MCUs it names: (path, [(mcu, avr)])."""
    d = os.path.join(work, "klipper_" + name)
    os.makedirs(os.path.join(d, "sd"), exist_ok=True)
    cfg = os.path.join(klipper, "config")
    shutil.copy(os.path.join(cfg, "sample-macros.cfg"), d)
    lines = []
    if name == "voron2":
        shutil.copy(os.path.join(cfg, "kit-voron2-250mm.cfg"), d)
        # sample-macros.cfg's beeper is on "ar37": the Arduino Mega names of sample-aliases.cfg.
        aliases = open(os.path.join(cfg, "sample-aliases.cfg")).read()
        mega = re.search(r"^\[board_pins arduino-mega\]\n(?:(?!\[).*\n)*", aliases, re.M).group(0)
        lines += ["[include kit-voron2-250mm.cfg]", "[include sample-macros.cfg]", mega]
        mcus = [("mcu", "atmega2560"), ("z", "atmega2560")]
    elif name == "ender3":
        shutil.copy(os.path.join(cfg, "printer-creality-ender3-2018.cfg"), d)
        lines += ["[include printer-creality-ender3-2018.cfg]", "[include sample-macros.cfg]",
                  "# sample-macros.cfg's beeper pin (ar37) is no Melzi pin: the Ender 3's (D27)",
                  "[pwm_cycle_time BEEPER_pin]", "pin: PA4"]
        mcus = [("mcu", "atmega1284p")]
    else:  # mk3s: the stock Einsy config with the MK3S's travel (Y from -4 for the intro line)
        # Without its [tmc2130 ...] sections: batch mode answers every driver register read
        # with 0, and the drivers' periodic check shut klippy down minutes into the print
        # ("TMC 'stepper_x' reports error: DRV_STATUS: 00000000 cs_actual=0(Reset?)").
        einsy = open(os.path.join(cfg, "generic-einsy-rambo.cfg")).read()
        einsy = re.sub(r"^\[tmc2130 [^\]]*\]\n(?:(?!\[).*\n)*", "", einsy, flags=re.M)
        with open(os.path.join(d, "generic-einsy-rambo.cfg"), "w") as f:
            f.write(einsy)
        lines += ["[include generic-einsy-rambo.cfg]", "[include sample-macros.cfg]",
                  "[stepper_x]", "position_max: 255",
                  "[stepper_y]", "position_min: -4", "position_max: 212.5",
                  "[stepper_z]", "position_max: 210",
                  "# The MK3S's intro line (PrusaSlicer's start G-code, carve's too) lays 12.5 mm",
                  "# of filament over 40 mm: 0.75 mm2, over the stock 4 x 0.4^2 = 0.64",
                  "[extruder]", "max_extrude_cross_section: 1.0",
                  "# ar37 is the Einsy's X step pin; its beeper is D84",
                  "[pwm_cycle_time BEEPER_pin]", "pin: PH2",
                  "# M73 for the LCD, as the MK3S Klipper configs have it",
                  "[display_status]"]
        mcus = [("mcu", "atmega2560")]
    lines += ["[virtual_sdcard]", "path: " + os.path.join(d, "sd"), ""]
    path = os.path.join(d, "printer.cfg")
    with open(path, "w") as f:
        f.write("\n".join(lines))
    return path, mcus


def run_klipper(klipper, setup, gcode, work, heat_model=True):
    """klippy in batch mode on gcode; without heat_model, plain klippy.py (every extrusion let
    through: only to time a file the heat model stopped)."""
    cfg, mcus = klipper_setup(klipper, setup, work)
    args = [cfg, "-i", gcode, "-o", "/dev/null", "-v"]
    for mcu, avr in mcus:
        dictionary, why = build_dictionary(klipper, avr, work)
        if dictionary is None:
            return {"skipped": why}
        args += ["-d", dictionary if mcu == "mcu" else "%s=%s" % (mcu, dictionary)]
    t0 = time.time()
    shim = ([os.path.abspath(__file__), "--klippy-shim", klipper] if heat_model
            else [os.path.join(klipper, "klippy", "klippy.py")])
    r = run([sys.executable] + shim + args, cwd=klipper, timeout=3600)
    log = r.stderr
    res = {"rc": r.returncode, "wall": time.time() - t0, "errors": [], "unknown": collections.Counter(),
           "heat": [], "print_time": None, "paused": 0}
    for line in log.splitlines():
        m = re.match(r"^(\w+):root:(.*)$", line)
        if not m:
            continue
        level, msg = m.groups()
        u = re.match(r'^Unknown command:"(.*)"$', msg)
        if u:
            res["unknown"][u.group(1)] += 1
        elif msg.startswith("heat model:"):
            res["heat"].append(msg[len("heat model: "):])
        elif msg.startswith("action:paused"):
            res["paused"] += 1
        elif level in ("WARNING", "ERROR") and "No log file specified" not in msg:
            res["errors"].append(msg)
        p = re.match(r"^Exiting \(print time ([\d.]+)s\)", msg)
        if p:
            res["print_time"] = float(p.group(1))
    res["ok"] = r.returncode == 0 and res["print_time"] is not None and not res["errors"]
    return res


if __name__ == "__main__":
    if len(sys.argv) > 2 and sys.argv[1] == "--klippy-shim":
        sys.exit(klippy_shim(sys.argv[2], sys.argv[3:]))
    sys.exit(__doc__)
