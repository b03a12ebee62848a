"""Bad input at every boundary of the command line (issue #12): each command line below ends with
exit code 2, exactly one line on stderr that names the parameter, nothing on stdout, and no
traceback, before any work is done (no output folder is left behind unless the folder itself is
the problem). Run in-process through `studies.cli.main`.

Placeholders: OUT a fresh output folder; FILE an existing file; RO a folder that cannot be written;
MISSING a path that does not exist; TEXT a text file that is neither JSON nor a tensile CSV; BIN a
binary file; LIST a JSON list; BADTOML a broken TOML file; JSONDIR a folder named x.json;
EPSA / FOOT valid design files; NANFIELD a design with NaN; UNKNOWNKEY a design with an unknown key.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from softcrawl.studies.cli import main

HUGE = "9" * 401  # a 401-digit integer (was an OverflowError)
BIG = str(10**30)

CASES: list[tuple[str, str]] = [
    # -- mesh: edge length, design fields of every part, design files, folders ------------------
    ("report --results MISSING --out OUT", "results"),
    ("report --results FILE --out OUT", "results"),
    ("replot MISSING", "results"),
    ("replot FILE", "results"),
    ("robot --pressures 100,40 --out OUT", "pressures"),
    ("robot --pressures 100,nan,60 --out OUT", "pressures"),
    ("robot --pressures 100,40,2000 --out OUT", "pressures"),
    ("robot --pressures 100,40,60 --first a,b,c --out OUT", "first"),
    ("robot --pressures 100,40,60 --steps 0 --out OUT", "steps"),
    ("robot --pressures 100,40,60 --rings -1 --out OUT", "rings"),
    ("robot --pressures 100,40,60 --d 5 --out OUT", "d"),
    ("robot --pressures 100,40,60 --d nan --out OUT", "d"),
    ("robot --pressures 100,40,60 --mesh huge --out OUT", "mesh"),
    ("robot --pressures 100,40,60 --material unobtainium --out OUT", "material"),
    ("robot --pressures 100,40,60 --out FILE", "out"),
    ("robot --pressures 100,40,60 --out RO/x", "out"),
    ("crawl --pipe-diameter 45 --out OUT", "pipe-diameter"),
    ("crawl --pipe-diameter 80 --out OUT", "pipe-diameter"),
    ("crawl --pipe-diameter nan --out OUT", "pipe-diameter"),
    ("crawl --gait gait9 --out OUT", "gait"),
    ("crawl --body beam --out OUT", "body"),
    ("crawl --pipe spiral --body fe --out OUT", "pipe"),
    ("crawl --pipe vertical-up --out OUT", "pipe"),  # the reduced model's pipe is straight
    ("crawl --bend-radius 60 --out OUT", "bend-radius"),
    ("crawl --body fe --pipe elbow --out OUT", "bend-radius"),
    ("crawl --body fe --pipe elbow --bend-radius 30 --out OUT", "bend-radius"),  # below the radius
    ("crawl --body fe --pipe elbow --bend-radius 39 --out OUT", "bend-radius"),  # below the clear wall
    ("crawl --body fe --pipe elbow --bend-radius -5 --out OUT", "bend-radius"),
    ("crawl --body fe --bend-radius 60 --out OUT", "bend-radius"),  # not an elbow
    ("crawl --body fe --backward --out OUT", "backward"),
    ("crawl --body fe --symmetric --out OUT", "symmetric"),
    ("crawl --body fe --mesher tetwild --out OUT", "mesher"),
    ("crawl --body fe --sectors 32 --out OUT", "sectors"),
    ("crawl --body fe --foot-angle 60 --out OUT", "foot-angle"),
    ("crawl --body fe --insertion-cache --out OUT", "insertion-cache"),
    ("crawl --body fe --gif --out OUT", "gif"),
    ("crawl --body fe --material unobtainium --out OUT", "material"),
    ("crawl --gait-plan FILE --out OUT", "gait-plan"),  # the reduced model has no plan
    ("crawl --time-limit 10 --out OUT", "time-limit"),  # the reduced model has no budget
    ("crawl --inertia --out OUT", "inertia"),  # the reduced model is quasi-static
    ("crawl --body fe --time-limit 0 --out OUT", "time-limit"),
    ("crawl --body fe --gait-plan MISSING --out OUT", "gait-plan"),
    ("crawl --body fe --gait-plan TEXT --out OUT", "gait-plan"),
    ("crawl --body fe --gait-plan BIN --out OUT", "gait-plan"),
    ("crawl --cycles 0 --out OUT", "cycles"),
    ("crawl --pressure 150 --out OUT", "pressure"),
    ("crawl --cycle-time 0 --out OUT", "cycle-time"),
    ("crawl --mu-smooth -0.1 --out OUT", "mu-smooth"),
    ("crawl --mesh-size 0.2 --out OUT", "mesh-size"),
    ("crawl --mesh-size 3 --out OUT", "mesh-size"),  # a tetwild setting on the revolved feet
    ("crawl --mesher tetwild --sectors 32 --out OUT", "sectors"),
    ("crawl --mesher tetwild --layers 2 --out OUT", "layers"),
    ("crawl --sectors 8 --out OUT", "sectors"),
    ("crawl --quick --wedge 5 --out OUT", "wedge"),  # does not divide the 24 sectors
    ("crawl --sectors 24 --wedge 24 --out OUT", "wedge"),  # a wedge of one sector
    ("crawl --wedge 0 --out OUT", "wedge"),
    ("crawl --mesher tetwild --wedge 4 --out OUT", "wedge"),
    ("crawl --body fe --wedge 4 --out OUT", "wedge"),
    ("crawl --body fe --wedge 3 --pipe elbow --bend-radius 80 --out OUT", "wedge"),  # no symmetry
    ("crawl --body fe --wedge 3 --gait-plan FILE --out OUT", "wedge"),
    ("crawl --body fe --wedge 3 --pipe bellows --out OUT", "wedge"),  # its snaps break the symmetry
    ("crawl --body fe --wedge 3 --gait gait2 --out OUT", "wedge"),  # unequal pressures
    ("study crawl --wedge 5 --out OUT", "wedge"),
    ("study crawl --quick --wedge 24 --out OUT", "wedge"),
    ("study fiber-turns --wedge 4 --out OUT", "wedge"),
    ("study feet --wedge 13 --out OUT", "wedge"),
    ("study optimise-feet --wedge 13 --out OUT", "wedge"),
    ("crawl --sectors 20 --out OUT", "sectors"),  # a valid mesh, but too coarse for the contact faces
    ("crawl --layers 0 --out OUT", "layers"),
    ("crawl --mesher gmsh --out OUT", "mesher"),
    ("crawl --steps 0 --out OUT", "steps"),
    ("crawl --schedule MISSING --out OUT", "schedule"),
    ("crawl --schedule TEXT --out OUT", "schedule"),
    ("crawl --backward --symmetric --out OUT", "symmetric"),
    ("crawl --backward --pipe-diameter 51 --out OUT", "pipe-diameter"),  # the flipped feet need > 52 mm
    ("crawl --out FILE", "out"),
    ("crawl --foot-angle 29 --out OUT", "foot-angle"),
    ("crawl --foot-angle 121 --out OUT", "foot-angle"),
    ("crawl --material rubber-90a --out OUT", "material"),
    ("crawl --material abs --out OUT", "material"),
    ("study crawl --material ecoflex-00-50 --out OUT", "material"),
    ("study crawl --workers 0 --out OUT", "workers"),
    ("study feet --material rubber-50a --out OUT", "material"),  # the hardness is the study's grid
    ("study feet --out OUT", "out"),  # no identified friction in OUT/identify/feet
    ("study feet --trials 3 --out OUT", "trials"),
    ("study rings --workers 0 --out OUT", "workers"),
    ("study workspace --material unobtainium --out OUT", "material"),
    ("mesh epsa --mesh-size nan --out OUT", "mesh-size"),
    ("mesh epsa --mesh-size 1e-6 --out OUT", "mesh-size"),
    ("mesh epsa --mesh-size -1 --out OUT", "mesh-size"),
    ("mesh epsa --mesh-size inf --out OUT", "mesh-size"),
    ("mesh epsa --mesh-size 0 --out OUT", "mesh-size"),
    ("mesh epsa --mesh-size abc --out OUT", "mesh-size"),
    ("mesh ring --mesh-size 0.02 --out OUT", "edge_length"),
    ("mesh epsa --length 1e12 --out OUT", "length"),
    ("mesh epsa --length nan --out OUT", "length"),
    ("mesh epsa --length -5 --out OUT", "length"),
    ("mesh epsa --length 0 --out OUT", "length"),
    ("mesh epsa --chamber-radius 9 --out OUT", "chamber_radius"),
    (f"mesh epsa --fiber-turns {HUGE} --out OUT", "fiber_turns"),
    ("mesh epsa --fiber-turns -3 --out OUT", "fiber_turns"),
    ("mesh epsa --fiber-turns 1000 --out OUT", "fiber_turns"),
    ("mesh epsa --fiber-turns 2.5 --out OUT", "fiber_turns"),
    ("mesh epsa --fiber-diameter 7 --out OUT", "fiber_diameter"),
    ("mesh epsa --end-cap-thickness 60 --out OUT", "end_cap_thickness"),
    ("mesh epsa --seal-head-thickness 0 --out OUT", "seal_head_thickness"),
    ("mesh epsa --outer-radius 1e308 --out OUT", "outer_radius"),
    ("mesh foot --angle 5e-324 --out OUT", "angle"),
    ("mesh foot --angle 190 --out OUT", "angle"),
    ("mesh foot --angle nan --out OUT", "angle"),
    (f"mesh foot --n-grooves {BIG} --out OUT", "n_grooves"),
    ("mesh foot --n-grooves -1 --out OUT", "n_grooves"),
    ("mesh foot --n-grooves 40 --out OUT", "n_grooves"),
    ("mesh foot --groove-height 5 --out OUT", "groove_height"),
    ("mesh foot --tip-radius 20 --out OUT", "tip_radius"),
    ("mesh foot --hub-thickness 1 --out OUT", "hub_thickness"),
    ("mesh foot --bore-radius 30 --out OUT", "bore_radius"),
    ("mesh foot --skirt-thickness inf --out OUT", "skirt_thickness"),
    ("mesh ring --hole-radius 13 --out OUT", "hole_radius"),
    ("mesh ring --outer-radius 10 --out OUT", "outer_radius"),
    ("mesh ring --bore-radius 5 --out OUT", "bore_radius"),
    ("mesh ring --thickness -1 --out OUT", "thickness"),
    ("mesh ring --d nan --out OUT", "d"),
    ("mesh robot --d 9 --out OUT", "d"),
    ("mesh robot --d 1e308 --out OUT", "d"),
    ("mesh robot --d 40 --out OUT", "foot.tip_radius"),
    ("mesh robot --n-rings 30 --out OUT", "n_rings"),
    (f"mesh robot --n-rings {HUGE} --out OUT", "n_rings"),
    ("mesh robot --epsa.chamber-radius 9 --out OUT", "epsa.chamber_radius"),
    ("mesh robot --epsa.fiber-turns -1 --out OUT", "epsa.fiber_turns"),
    ("mesh robot --foot.angle 190 --out OUT", "foot.angle"),
    ("mesh robot --ring.outer-radius 40 --out OUT", "ring.outer_radius"),
    ("mesh robot --pipe-diameter-min 80 --out OUT", "pipe_diameter_min"),
    ("mesh robot --pipe-diameter-max nan --out OUT", "pipe_diameter_max"),
    ("mesh epsa --out FILE", "out"),
    ("mesh epsa --out FILE/sub", "out"),
    ("mesh epsa --out RO", "out"),
    ("mesh foot --out RO/sub", "out"),
    ("mesh epsa --design MISSING.json --out OUT", "design"),
    ("mesh epsa --design TEXT --out OUT", "design"),
    ("mesh epsa --design BIN --out OUT", "design"),
    ("mesh epsa --design LIST --out OUT", "design"),
    ("mesh epsa --design BADTOML --out OUT", "design"),
    ("mesh epsa --design design.yaml --out OUT", "design"),
    ("mesh epsa --design JSONDIR --out OUT", "design"),
    ("mesh foot --design EPSA --out OUT", "design"),
    ("mesh epsa --design NANFIELD --out OUT", "length"),
    ("mesh epsa --design UNKNOWNKEY --out OUT", "colour"),
    ("mesh epsa --cache-dir FILE --out OUT", "cache-dir"),
    ("mesh tube --out OUT", "tube"),
    ("mesh epsa --radius 3 --out OUT", "radius"),
    ("mesh", "kind"),
    ("mesh epsa", "out"),
    # -- epsa: design, pressures, material, mesh, convergence, loads, folders -----------------
    ("epsa --length 1e12 --out OUT", "length"),
    ("epsa --length nan --out OUT", "length"),
    ("epsa --chamber-radius 9.5 --out OUT", "chamber_radius"),
    ("epsa --chamber-radius -1 --out OUT", "chamber_radius"),
    (f"epsa --fiber-turns {HUGE} --out OUT", "fiber_turns"),
    ("epsa --fiber-turns -1 --out OUT", "fiber_turns"),
    ("epsa --fiber-turns 1e3 --out OUT", "fiber_turns"),
    ("epsa --outer-radius inf --out OUT", "outer_radius"),
    ("epsa --pressures 20,nan,40 --out OUT", "pressures"),
    ("epsa --pressures=-10,20 --out OUT", "pressures"),
    ("epsa --pressures 0:100:1e-4 --out OUT", "pressures"),
    ("epsa --pressures 100:0:20 --out OUT", "pressures"),
    ("epsa --pressures 0:100:0 --out OUT", "pressures"),
    ("epsa --pressures 0:100:-20 --out OUT", "pressures"),
    ("epsa --pressures 40,20 --out OUT", "pressures"),
    ("epsa --pressures 20,20 --out OUT", "pressures"),
    ("epsa --pressures= --out OUT", "pressures"),
    ("epsa --pressures 0 --out OUT", "pressures"),
    ("epsa --pressures 0:2000:100 --out OUT", "pressures"),
    ("epsa --pressures abc --out OUT", "pressures"),
    ("epsa --pressures 20,inf --out OUT", "pressures"),
    ("epsa --pressures 1:2:3:4 --out OUT", "pressures"),
    ("epsa --pressures 0:nan:10 --out OUT", "pressures"),
    ("epsa --material ecoflex-00-50@ --out OUT", "material"),
    ("epsa --material ecoflex-00-50@mu=1e12 --out OUT", "material"),
    ("epsa --material ecoflex-00-50@mu=nan --out OUT", "material"),
    ("epsa --material ecoflex-00-50@mu=-1 --out OUT", "material"),
    ("epsa --material ecoflex-00-50@mu=0 --out OUT", "material"),
    ("epsa --material ecoflex-00-50@nu=0.4 --out OUT", "material"),
    ("epsa --material unobtainium --out OUT", "material"),
    ("epsa --material abs --out OUT", "material"),
    ("epsa --material ecoflex-00-50-fit@mu=1e-9 --out OUT", "material"),
    ("epsa --mesh-size inf --out OUT", "mesh-size"),
    ("epsa --mesh-size nan --out OUT", "mesh-size"),
    ("epsa --mesh-size 0 --out OUT", "mesh-size"),
    ("epsa --mesh-size 1e-9 --out OUT", "mesh-size"),
    ("epsa --mesh-size 0.5 --out OUT", "mesh_size"),
    ("epsa --length 1000 --mesh-size 1 --out OUT", "mesh_size"),
    ("epsa --convergence 1e-9 --out OUT", "convergence"),
    ("epsa --convergence 10,nan --out OUT", "convergence"),
    ("epsa --convergence 5,10 --out OUT", "convergence"),
    ("epsa --convergence abc --out OUT", "convergence"),
    ("epsa --convergence 10,5,4,3,2.5,2,1.9,1.8,1.7 --out OUT", "convergence"),
    ("epsa --convergence 10,0.5 --out OUT", "convergence"),
    ("epsa --side-load nan --out OUT", "side-load"),
    ("epsa --side-load -1 --out OUT", "side-load"),
    ("epsa --side-load 5 --out OUT", "side-load"),
    ("epsa --side-load 1e-4 --guided --out OUT", "side_load"),
    ("epsa --side-load 1e-4 --blocked --out OUT", "side_load"),
    ("epsa --blocked --guided --out OUT", "blocked"),
    ("epsa --fibers braid --out OUT", "fibers"),
    ("epsa --out FILE", "out"),
    ("epsa --out RO", "out"),
    ("epsa --design MISSING.json --out OUT", "design"),
    ("epsa --design TEXT --out OUT", "design"),
    ("epsa --design FOOT --out OUT", "kind"),
    ("epsa", "out"),
    # -- verify ----------------------------------------------------------------------------------
    ("verify --case nope", "case"),
    ("verify --json JSONDIR", "json"),
    ("verify --json FILE/sub.json", "json"),
    ("verify --json RO/v.json", "json"),
    # -- material --------------------------------------------------------------------------------
    ("material show nope", "material"),
    ("material show ecoflex-00-50@", "material"),
    ("material fit --data nope", "data"),
    ("material fit --data BIN", "data"),
    ("material fit --data JSONDIR", "data"),
    ("material fit --data TEXT", "data"),
    ("material fit --max-strain -1", "max-strain"),
    ("material fit --max-strain nan", "max-strain"),
    ("material fit --max-strain inf", "max-strain"),
    ("material fit --max-strain 1e-9", "max_strain"),
    ("material fit --model mooney", "model"),
    ("material fit --out FILE", "out"),
    ("material fit --out RO", "out"),
    ("material fit-table --max-strain 0", "max-strain"),
    ("material", "material_command"),
    ("material show", "name"),
    # -- model: statics, kinematics, loads, identify ---------------------------------------------
    ("model statics --pressure -1", "pressure"),
    ("model statics --pressure nan", "pressure"),
    ("model statics --pressure 1e12", "pressure"),
    ("model statics --pressure 60 --g nan", "g"),
    ("model statics --pressure 60 --g -1", "g"),
    ("model statics --pressure 60 --actuator 4", "actuator"),
    ("model statics", "pressure"),
    ("model fk --lengths 100 0 100", "lengths"),
    ("model fk --lengths 100 nan 100", "lengths"),
    ("model fk --lengths 1e12 100 100", "lengths"),
    ("model fk --lengths 100 100", "lengths"),
    ("model fk --lengths 100 110 120 --d 0", "d"),
    ("model fk --lengths 100 110 120 --d nan", "d"),
    ("model ik --tip 0 0 -1", "tip"),
    ("model ik --tip nan 0 1", "tip"),
    ("model ik --tip 1e12 0 1", "tip"),
    ("model ik --tip 10 20 100 --d -1", "d"),
    ("model load --robot-mass nan", "robot-mass"),
    ("model load --robot-mass -1", "robot-mass"),
    ("model load --force inf", "force"),
    ("model load --force 1e12", "force"),
    ("model load --g 0", "g"),
    ("model speed --friction nan", "friction"),
    ("model speed --friction -1", "friction"),
    ("model speed --pressure 150", "pressure"),
    ("model speed --cycle 0", "cycle"),
    ("model speed --paper-speed nan", "paper-speed"),
    ("model speed --g nan", "g"),
    ("model identify --table MISSING.csv", "table"),
    ("model identify --table BIN", "table"),
    ("model identify --table TEXT", "table"),
    ("model identify --table JSONDIR", "table"),
    ("model identify --table TEXT --breakpoint nan", "breakpoint"),
    ("model identify --table TEXT --breakpoint 150", "breakpoint"),
    ("model identify --table TEXT --mass nan", "mass"),
    # -- model: workspace, plan, elbow-scan ------------------------------------------------------
    ("model workspace --n 100000 --out OUT", "n"),
    ("model workspace --n 1 --out OUT", "n"),
    ("model workspace --n 2.5 --out OUT", "n"),
    ("model workspace --d nan --out OUT", "d"),
    ("model workspace --d 0 --out OUT", "d"),
    ("model workspace --out FILE", "out"),
    ("model workspace --out RO", "out"),
    ("model plan --pipe straight --step 0 --out OUT", "step"),
    ("model plan --pipe straight --step 3 --out OUT", "step"),
    ("model plan --pipe straight --step nan --out OUT", "step"),
    ("model plan --pipe straight --step 0.01 --out OUT", "step"),
    ("model plan --pipe straight --diameter 1e12 --out OUT", "diameter"),
    ("model plan --pipe straight --diameter nan --out OUT", "diameter"),
    ("model plan --pipe elbow --out OUT", "bend-radius"),
    ("model plan --pipe elbow --bend-radius -5 --out OUT", "bend-radius"),
    ("model plan --pipe elbow --bend-radius inf --out OUT", "bend-radius"),
    ("model plan --pipe straight --length 0 --out OUT", "length"),
    ("model plan --pipe elbow --bend-radius 60 --exit-length nan --out OUT", "exit-length"),
    ("model plan --pipe straight --beam 0 --out OUT", "beam"),
    ("model plan --pipe straight --beam 1000 --out OUT", "beam"),
    ("model plan --pipe straight --step 1 --beam 64 --out OUT", "beam"),
    ("model plan --pipe straight --search continuous --out OUT", "search"),
    ("model plan --pipe elbow --bend-radius 60 --search continuous --cycles 0 --out OUT", "cycles"),
    ("model plan --pipe elbow --bend-radius 60 --search continuous --cycles 1000 --out OUT", "cycles"),
    ("model plan --pipe elbow --bend-radius 60 --search bfs --body epsa --out OUT", "search"),
    ("model plan --pipe straight --out FILE", "out"),
    ("model plan --pipe tube --out OUT", "pipe"),
    ("model elbow-scan --radii nan", "radii"),
    ("model elbow-scan --radii -5", "radii"),
    ("model elbow-scan --radii 1e12", "radii"),
    ("model elbow-scan --radii " + " ".join(["60"] * 51), "radii"),
    ("model elbow-scan --radii 60 --step 0", "step"),
    ("model elbow-scan --radii 60 --step 7", "step"),
    ("model elbow-scan --radii 60 --beam 0", "beam"),
    ("model elbow-scan --radii 60 --diameter nan", "diameter"),
    ("model elbow-scan --radii 60 --search continuous --body epsa", "search"),
    ("model nope", "model_command"),
    # -- study -----------------------------------------------------------------------------------
    ("study fiber-turns --mesh-size inf --out OUT", "mesh-size"),
    ("study fiber-turns --mesh-size nan --out OUT", "mesh-size"),
    ("study fiber-turns --mesh-size 0.5 --out OUT", "mesh_size"),
    ("study fiber-turns --simulator nocolon --out OUT", "simulator"),
    ("study fiber-turns --simulator no_such_module_x:f --out OUT", "simulator"),
    ("study fiber-turns --simulator softcrawl.studies.cli:no_such_function --out OUT", "simulator"),
    ("study fiber-turns --simulator softcrawl.studies.cli:EXIT_INPUT --out OUT", "simulator"),
    ("study fiber-turns --material unobtainium --out OUT", "material"),
    ("study fiber-turns --material ecoflex-00-50@ --out OUT", "material"),
    ("study fiber-turns --material abs --out OUT", "material"),
    ("study fiber-turns --workers 0 --out OUT", "workers"),
    ("study fiber-turns --workers 1000 --out OUT", "workers"),
    ("study optimise-actuator --trials 0 --out OUT", "trials"),
    (f"study optimise-actuator --trials {BIG} --out OUT", "trials"),
    ("study optimise-actuator --seed -1 --out OUT", "seed"),
    ("study fiber-turns --out FILE", "out"),
    ("study fiber-turns --out RO", "out"),
    ("study fiber-turns --storage study.db --out OUT", "storage"),
    ("study no-such-study --out OUT", "name"),
    ("study optimise-actuator --sampler cmaes --out OUT", "sampler"),
    # -- table1, calibrate, the command itself --------------------------------------------------
    ("table1 --material unobtainium --out OUT", "material"),
    ("table1 --material ecoflex-00-50@mu=1e12 --out OUT", "material"),
    ("table1 --results MISSING --out OUT", "results"),
    ("table1 --out FILE", "out"),
    ("table1 --out RO", "out"),
    ("calibrate --material unobtainium --out OUT", "material"),
    ("calibrate --material abs --out OUT", "material"),
    ("calibrate --material ecoflex-00-50@ --out OUT", "material"),
    ("calibrate --out FILE", "out"),
    ("nope", "command"),
    ("", "command"),
    # -- issue 30: inputs that got through ----------------------------------------------------
    # an empty output folder name (the work went into the current folder)
    ("study chamber-radius --out=", "out"),
    ("crawl --out=", "out"),
    ("robot --pressures 100,40,60 --out=", "out"),
    ("epsa --out=", "out"),
    ("table1 --out=", "out"),
    ("calibrate --out=", "out"),
    ("report --results RESULTS --out=", "out"),
    # report checks --out before it builds
    ("report --results RESULTS --out FILE", "out"),
    ("report --results RESULTS --out RO/x", "out"),
    # options that do not apply to the study (its declaration's options)
    ("study rings --trials 5 --out OUT", "trials"),
    ("study chamber-radius --sampler tpe --out OUT", "sampler"),
    ("study fiber-turns --seed 3 --out OUT", "seed"),
    ("study workspace --workers 2 --out OUT", "workers"),
    ("study workspace --workers 1 --out OUT", "workers"),
    ("study crawl --mesh-size 5 --out OUT", "mesh-size"),
    ("study groove --fibers sheet --out OUT", "fibers"),
    ("study paper-material --storage sqlite:///x.db --out OUT", "storage"),
    ("study kp-mismatch --retry-failed --out OUT", "retry-failed"),
    ("study workspace --max-memory 2 --out OUT", "max-memory"),
    ("study foot --simulator tests.studies.fakes:fake_simulate --out OUT", "simulator"),
    ("study chamber-radius --max-memory 0 --out OUT", "max-memory"),
    ("study chamber-radius --max-memory nan --out OUT", "max-memory"),
    # optimise-feet (issue 29, step 7): its identification, its options
    ("study optimise-feet --out OUT", "out"),  # no identified friction in OUT/identify/feet
    # a study that takes no material (its declaration's default_material None) refuses --material:
    # optimise-feet's hardness is a design variable, the others read or scan theirs
    ("study optimise-feet --material rubber-50a --out OUT", "material"),
    ("study identify-feet --material rubber-70a --out OUT", "material"),
    ("study predict-crawl --material rubber-70a --out OUT", "material"),
    ("study paper-material --material ecoflex-00-50 --out OUT", "material"),
    ("study optimise-feet --confirm 0 --out OUT", "confirm"),
    ("study optimise-feet --confirm 11 --out OUT", "confirm"),
    ("study foot --confirm 2 --out OUT", "confirm"),
    ("study optimise-feet --mesh-size 5 --out OUT", "mesh-size"),
    ("study optimise-feet --simulator tests.studies.fakes:fake_simulate --out OUT", "simulator"),
    # a --simulator of the wrong signature, probed before the sweep
    ("study chamber-radius --simulator tests.studies.fakes:fake_robot_cases --out OUT", "simulator"),
    ("study rings --simulator tests.studies.fakes:fake_simulate --out OUT", "simulator"),
    ("study identify --simulator tests.studies.fakes:fake_simulate --out OUT", "simulator"),
    ("study chamber-radius --simulator os.path:join --out OUT", "simulator"),
    # replot and table1 on a folder with no results
    ("replot EMPTYDIR", "results"),
    ("table1 --results EMPTYDIR --out OUT", "results"),
    ("table1 --out EMPTYDIR", "results"),
    # calibrate takes Neo-Hookean presets only
    ("calibrate --material ecoflex-00-50-yeoh --out OUT", "material"),
    ("calibrate --material ecoflex-00-50-gent --out OUT", "material"),
    # a negative pressure first in a list or range (was argparse's "expected one argument")
    ("epsa --pressures -10,20,30 --out OUT", "pressures"),
    ("epsa --pressures -10:100:20 --out OUT", "pressures"),
    ("epsa --pressures -0.5,20 --out OUT", "pressures"),
    ("robot --pressures -10,20,30 --out OUT", "pressures"),
    ("robot --pressures 100,40,60 --first -5,0,0 --out OUT", "first"),
    # a design file without a kind
    ("mesh epsa --design NOKIND --out OUT", "kind"),
]


def _unwritable(tmp_path: Path) -> str:
    """A folder that cannot be written: chmod 555 for a normal user; root writes anywhere, so
    there the kernel's /sys (EPERM) stands in for it."""
    if os.geteuid() != 0:
        ro = tmp_path / "ro"
        ro.mkdir()
        ro.chmod(0o555)
        return str(ro)
    if not Path("/sys").is_dir():
        pytest.skip("running as root without /sys: no folder is read-only for root")
    return "/sys"


@pytest.fixture
def files(tmp_path):
    from softcrawl.geometry.design import EPSADesign, FootDesign

    paths = {
        "OUT": tmp_path / "out",
        "FILE": tmp_path / "file.txt",
        "MISSING": tmp_path / "missing",
        "TEXT": tmp_path / "notes.json",
        "BIN": tmp_path / "binary.json",
        "LIST": tmp_path / "list.json",
        "BADTOML": tmp_path / "bad.toml",
        "JSONDIR": tmp_path / "folder.json",
        "EPSA": tmp_path / "epsa.json",
        "FOOT": tmp_path / "foot.json",
        "NANFIELD": tmp_path / "nan.json",
        "UNKNOWNKEY": tmp_path / "unknown.json",
        "EMPTYDIR": tmp_path / "empty",
        "NOKIND": tmp_path / "nokind.json",
        "RESULTS": Path(__file__).resolve().parents[3] / "results",
    }
    paths["FILE"].write_text("a file, not a folder\n")
    paths["TEXT"].write_text("pressure and length, but not as JSON or CSV columns\n")
    paths["BIN"].write_bytes(bytes(range(256)) * 4)
    paths["LIST"].write_text("[1, 2, 3]")
    paths["BADTOML"].write_text("length = = 3\n")
    paths["JSONDIR"].mkdir()
    EPSADesign().save(paths["EPSA"])
    FootDesign().save(paths["FOOT"])
    paths["NANFIELD"].write_text('{"kind": "epsa", "length": NaN}')
    paths["UNKNOWNKEY"].write_text(json.dumps({"kind": "epsa", "colour": "red"}))
    paths["EMPTYDIR"].mkdir()
    paths["NOKIND"].write_text(json.dumps({"chamber_radius": 3.0}))
    return {k: str(v) for k, v in paths.items()}


def _argv(line: str, files: dict[str, str], tmp_path: Path) -> list[str]:
    out = []
    for word in line.split():
        head, sep, rest = word.partition("=")
        key, slash, tail = (rest if sep else word).partition("/")
        key, dot, suffix = key.partition(".")
        if key == "RO":
            value = _unwritable(tmp_path)
        elif key in files:
            value = files[key]
        else:
            out.append(word)
            continue
        value += dot + suffix + slash + tail
        out.append(f"{head}={value}" if sep else value)
    return out


@pytest.mark.timeout(60)
@pytest.mark.parametrize("line, parameter", CASES, ids=[c[0][:70] or "(empty)" for c in CASES])
def test_bad_input_is_one_line_naming_the_parameter_and_exit_2(line, parameter, files, tmp_path, capfd):
    code = main(_argv(line, files, tmp_path))
    out, err = capfd.readouterr()
    lines = err.strip().splitlines()
    assert code == 2, (code, out, err)
    assert len(lines) == 1, err
    assert "Traceback" not in err and out == "", (out, err)
    normal = lines[0].replace("-", "_")
    assert parameter.replace("-", "_") in normal, lines[0]
    if "OUT" in line.split() and parameter not in ("out",):
        assert not Path(files["OUT"]).exists(), "the output folder was made before the input was checked"


def test_the_suite_covers_every_subcommand():
    from softcrawl.studies.cli import build_parser

    parser = build_parser()
    (sub,) = [a for a in parser._actions if a.dest == "command"]
    covered = {line.split()[0] for line, _ in CASES if line}
    assert set(sub.choices) <= covered
    assert len(CASES) >= 150


def _api_calls():
    from softcrawl import materials
    from softcrawl.analytic import kinematics, loads, workspace
    from softcrawl.analytic.pipe import Pipe
    from softcrawl.analytic.planner import plan
    from softcrawl.fem.laws import NeoHookean, Yeoh
    from softcrawl.geometry.design import EPSADesign
    from softcrawl.studies.epsa.model import MeshSettings, resolve_mesh

    huge = 10**400
    return [
        (
            "material mu",
            lambda: materials.Material(name="x", law=NeoHookean.nearly_incompressible(huge), density=1e-9),
        ),
        (
            "material density",
            lambda: materials.Material(name="x", law=NeoHookean.nearly_incompressible(0.03), density=huge),
        ),
        (
            "yeoh",
            lambda: materials.Material(name="y", law=Yeoh.nearly_incompressible(0.01, huge, 0), density=1e-9),
        ),
        ("with_mu", lambda: materials.get_material("ecoflex-00-50").with_mu(1e300)),
        ("get_material", lambda: materials.get_material(huge)),
        ("forward", lambda: kinematics.forward([huge, 100.0, 100.0])),
        ("forward d", lambda: kinematics.forward([100.0, 110.0, 120.0], d=huge)),
        ("inverse", lambda: kinematics.inverse([0.0, 0.0, 100.0], d=float("nan"))),
        ("workspace", lambda: workspace.sample(n=huge)),
        ("load", lambda: loads.theoretical_load(8.42, float("nan"), 9810.0)),
        ("speed", lambda: loads.crawl_speed((), 100.0, float("nan"))),
        ("pipe", lambda: Pipe("straight", diameter=huge)),
        ("plan step", lambda: plan(Pipe("straight"), step_kpa=0.0)),
        ("plan beam", lambda: plan(Pipe("straight"), beam=huge)),
        ("mesh size", lambda: MeshSettings.from_size(5e-324, EPSADesign())),
        ("mesh cost", lambda: resolve_mesh(EPSADesign(length=1000.0), mesh_size=0.2)),
    ]


@pytest.mark.parametrize("index", range(16))
def test_python_api_bad_numbers_raise_input_errors(index):
    """The library entry points behind the commands: a huge integer, NaN or a subnormal is an
    `InputError` naming a parameter, never an OverflowError or ZeroDivisionError."""
    from softcrawl.errors import InputError

    name, call = _api_calls()[index]
    with pytest.raises(InputError) as info:
        call()
    assert info.value.parameter and len(str(info.value)) < 300, name


@pytest.mark.parametrize(
    "spec, expected",
    [
        ("0:100:20", (20.0, 40.0, 60.0, 80.0, 100.0)),
        ("0:100:30", (30.0, 60.0, 90.0)),
        ("10,30,50", (10.0, 30.0, 50.0)),
        ("0,20", (20.0,)),
        ("5:10:5", (5.0, 10.0)),
    ],
)
def test_valid_pressures_parse_as_before(spec, expected):
    from softcrawl.studies.commands.options import parse_pressures

    assert parse_pressures(spec) == pytest.approx(expected)


def test_a_design_without_kind_says_the_key_is_missing(files, tmp_path, capfd):
    assert main(["mesh", "epsa", "--design", files["NOKIND"], "--out", files["OUT"]]) == 2
    err = capfd.readouterr().err
    assert "the key 'kind' is missing" in err and "None" not in err, err


def test_a_folder_that_cannot_be_created_is_named_beside_the_folder_at_fault(files, tmp_path, capfd):
    """`cannot write to /proc` for --out /proc/x named the wrong path: the message names both."""
    ro = _unwritable(tmp_path)
    assert main(["table1", "--out", f"{ro}/x/y"]) == 2
    err = capfd.readouterr().err.strip()
    assert f"cannot create {ro}/x/y: cannot write to {ro}" in err, err


def test_a_negative_number_alone_is_still_an_argument():
    from softcrawl.studies.cli import attach_negative_values

    argv = ["model", "ik", "--tip", "-10", "20", "100", "--pressures", "-10,20", "--a=-1,2", "--", "-3,4"]
    assert attach_negative_values(argv) == [
        "model", "ik", "--tip", "-10", "20", "100", "--pressures=-10,20", "--a=-1,2", "--", "-3,4"
    ]  # fmt: skip
