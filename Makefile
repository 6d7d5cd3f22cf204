# The two commands a newcomer runs are `make demo` and `make test`; both set up first.
SHELL := /bin/bash
ENV := . tools/env.sh &&
PY := .venv/bin/python
comma := ,
# Headless pygame everywhere we run without a screen.
export SDL_VIDEODRIVER ?= dummy
export SDL_AUDIODRIVER ?= dummy
export PYGAME_HIDE_SUPPORT_PROMPT := 1

.PHONY: setup demo doctor demo-sensor lab-twin test lint clean bench

# The lab's robot, chosen once for everything started from here (docs/lab-day.md, "Another Franka arm"):
# ROBOT=fr3 is the Franka Research 3 (hri_teleop/core/robots/fr3.yaml), a path names a profile of one's own;
# unset: the Panda, or HRI_ROBOT as the shell has it.
ifneq ($(ROBOT),)
export HRI_ROBOT := $(ROBOT)
endif

setup:
	@bash tools/setup.sh

# The whole lab simulated: teleoperation.launch sim:=true with the default scenario (~25 s); ROBOT=fr3 on the FR3.
demo: setup
	@$(ENV) $(PY) -m hri_teleop.apps.demo $(DEMO_ARGS)

# Preflight of a lab station (docs/lab-day.md): one line per part, ok or the fix, in under 10 s.
# WALK=1 also walks through the pad's buttons, its rumble and a full press of the piston;
# DOCTOR_ARGS="--port /dev/ttyACM1" names the Arduino's port. At home it checks the simulated lab.
doctor: setup
	@$(ENV) $(PY) -m hri_teleop.apps.doctor $(if $(filter-out 0,$(WALK)),--walk) $(DOCTOR_ARGS)

# Only the sensor stage (handout Ex. 6): sensor.launch with the simulated press profile.
demo-sensor: setup
	@$(ENV) $(PY) -m hri_teleop.apps.demo_sensor

# The lab twin (docs/lab-day.md, "Before the first session"): a master that looks like the lab PC's
# (franka_control, franka_gripper, joint_state_publisher, serial_node with a rosserial board on a pty)
# and counts what reaches it, with the lab PC's installed franka_control and rosserial_python so a
# student's teleoperation.launch runs on it. Prints the URI and package path to export; takes press 700 2,
# activate, deactivate, report on standard input; Ctrl-C stops everything.
# LAB_TWIN_ARGS="--deactivated --publish-period-ms 300", or "--bare": only the master and the board.
lab-twin: setup
	@$(ENV) $(PY) -m hri_teleop.apps.lab_twin $(LAB_TWIN_ARGS)

# TEST_JOBS test workers (default two per core: much of a worker's time is spent waiting on real
# time -- a launch, a kernel, a simulated second. On the 2-core machine, from a fresh clone: two
# workers 17.5 min, three 15.9, four 14.4 to 15.8 min of tests (2026-11-27; four: 10.8 min on
# 2026-11-28, after grading stopped waiting for clean shutdowns); TEST_JOBS=0 runs in one process), each test
# file on one worker, the longest files first (tests/conftest.py). The 30 slowest tests are listed
# at the end, so every CI log shows where the time goes (no test judges a time: speed is `make bench`'s).
TEST_JOBS ?= $(shell echo $$(( $$(nproc 2>/dev/null || echo 1) * 2 )))
test: setup
	@$(ENV) $(PY) -m pytest -q -p no:cacheprovider --durations=30 $(if $(filter-out 0,$(TEST_JOBS)),-n $(TEST_JOBS) --dist loadfile --no-loadscope-reorder) $(PYTEST_ARGS)

# The student bundle's container for real (tests/container): a Debian base from debootstrap, the
# bundle's `make image`, `make check` inside, JupyterLab through `docker compose up` in a browser.
# Needs dockerd, debootstrap and docker-compose (Debian: docker.io debootstrap docker-compose);
# not part of `make test` (about 10 minutes, and it downloads what a student's first build does).
.PHONY: test-container
test-container: setup
	@$(ENV) HRI_TEST_CONTAINER=1 $(PY) -m pytest -q -p no:cacheprovider -s tests/container $(PYTEST_ARGS)

# Benchmarks (README "Performance"): force-to-rumble latency, twist timing, simulation speed,
# grading throughput and determinism, notebooks and setup, make doctor; each row beside its reference
# from the same run and its machine (CPU, cores, Python, load average, idle or busy).
# BENCH=latency,timing,... picks some (default: all); results in out/bench/results.{md,json}.
# Not part of `make test`, which runs each benchmark in its smoke size (tests/bench/).
bench: setup
	@$(ENV) $(PY) -m benchmarks $(subst $(comma), ,$(BENCH)) --out out/bench $(if $(JOBS),--jobs $(JOBS))

# Mutation testing (docs/testing.md): mutmut over hri_teleop/core/ and the late policy, on a copy of the
# checkout in out/mutants/work (the working tree is left as it was), each mutant judged by the unit tests
# of its own module; prints the mutants per module and every survivor as file:line: old -> new.
# MODULES=hri_teleop/core/joints.py,... mutates only those; JOBS=n mutants at once (default: the cores).
# Not part of `make test` (a full run takes tens of minutes).
# constraints.txt: the exact versions of .venv (Python 3.11) and .venv38 (Python 3.8), which every
# install through tools/setup.sh takes (make setup, the student bundle, Gradescope); run it after a
# tested upgrade, at the start of a term (docs/testing.md, "Pinned versions").
.PHONY: pins
pins: setup
	@$(ENV) $(PY) tools/pins.py

.PHONY: mutants
mutants: setup
	@$(ENV) $(PY) tools/mutants.py $(if $(MODULES),--only $(subst $(comma), ,$(MODULES))) $(if $(JOBS),--jobs $(JOBS))

# catkin_lint on the lab package, ruff on the whole checkout (notebooks too), mypy --strict on the
# package (pyproject.toml's [tool.ruff] and [tool.mypy]); `make test` runs all three too.
lint: setup
	@$(ENV) catkin_lint --offline -W2 --strict hri_lab
	@$(ENV) ruff check .
	@$(ENV) $(PY) -m mypy

clean:
	rm -rf .venv build out .pytest_cache .hypothesis

# Autograder (hri_teleop.grading; solutions/README.md). `make traces` rewrites the public
# reference bags in grading/traces/ (byte-identical on every run), `make templates` the
# student templates from solutions/ into build/templates/, and `make grade` grades every
# submission in DIR (default nbgrader's notebooks/submitted/) into OUT (default out/grades):
# an nbgrader course's submitted/<student>/<assignment>/ gets nbgrader's autograde and
# generate_feedback as well (notebooks/README.md). JOBS=n at once (default: the cores),
# TIMEOUT=s per submission, CHECKS=a,b limits the checks of the student files.
# STUDENT=id regrades one student (the others' rows kept), LATE=late.yaml the late policy;
# OUT also gets report.html (the class report) and lms.csv (grading/README.md); REPORT=1
# grades nothing and writes those again (after grading by hand, or a changed late.yaml).
# Student code runs in bubblewrap; where it cannot, make grade refuses unless UNSANDBOXED=1
# (the notebooks' kernels then run with the grader's rights; the output and report.html say so first).
traces: setup
	@$(ENV) $(PY) -m hri_teleop.apps.grade traces

templates: setup
	@$(ENV) $(PY) -m hri_teleop.apps.grade templates

grade: setup
	@$(ENV) $(PY) -m hri_teleop.apps.grade batch $(or $(DIR),notebooks/submitted) --out $(or $(OUT),out/grades) $(if $(JOBS),--jobs $(JOBS)) $(if $(TIMEOUT),--timeout $(TIMEOUT)) $(if $(CHECKS),--checks $(CHECKS)) $(if $(STUDENT),--student $(STUDENT)) $(if $(LATE),--late $(LATE)) $(if $(filter-out 0,$(REPORT)),--report-only) $(if $(filter-out 0,$(UNSANDBOXED)),--unsandboxed)

# Gradescope (grading/README.md, section Gradescope): out/gradescope/autograder.zip with setup.sh and
# run_autograder at its root, for a programming assignment on Gradescope's Ubuntu 22.04 base image.
# CHECKS=a,b grades some of the checks (default: all), OUT=dir writes it elsewhere; UNSANDBOXED=1 grades
# uploaded notebooks with the grader's rights where Gradescope's container cannot run bubblewrap.
.PHONY: gradescope
gradescope: setup
	@$(ENV) $(PY) -m hri_teleop.apps.gradescope build --out $(or $(OUT),out/gradescope) $(if $(CHECKS),--checks $(CHECKS)) $(if $(filter-out 0,$(UNSANDBOXED)),--unsandboxed)

# The instructor's steps after make grade (docs/instructors.md, The cycle), each from a fresh shell: nbgrader is
# in .venv only. DIR=... is the course or its submitted/ (default notebooks/), OUT=... make grade's results.
# `make formgrader`: JupyterLab on the course at nbgrader's formgrader, to grade the written answers by hand
# (FORMGRADER_ARGS="--no-browser --port 8890" go to jupyter lab; Ctrl-C ends it). `make feedback`, after grading by
# hand: nbgrader's feedback again with the manual points, each page with the student's files' points and feedback,
# then grades.csv, lms.csv and report.html (as REPORT=1). `make release-feedback`: nbgrader release_feedback of every
# assignment (students handed in with nbgrader submit; the others' feedback folders are named, to hand out).
# `make nbgrader ARGS="collect preparation"`: any nbgrader command in the course folder.
.PHONY: formgrader feedback release-feedback nbgrader
formgrader: setup
	@$(ENV) $(PY) -m hri_teleop.apps.instructor formgrader $(or $(DIR),notebooks) $(FORMGRADER_ARGS)

feedback: setup
	@$(ENV) $(PY) -m hri_teleop.apps.instructor feedback $(or $(DIR),notebooks) --out $(or $(OUT),out/grades) $(if $(LATE),--late $(LATE))

release-feedback: setup
	@$(ENV) $(PY) -m hri_teleop.apps.instructor release-feedback $(or $(DIR),notebooks)

nbgrader: setup
	@$(ENV) $(PY) -m hri_teleop.apps.instructor nbgrader --dir $(or $(DIR),notebooks) $(ARGS)

# Firmware (firmware/README.md): both Arduino sketches for the Uno with Debian's AVR
# toolchain (flash and RAM use against 32 KB / 2 KB), and the simulated Uno (simavr) the
# tests run the plain-serial sketch on. ROS_LIB=... points at a rosserial Arduino library;
# without one the rosserial sketch is skipped with a one-line note.
.PHONY: firmware
firmware: setup
	@$(MAKE) --no-print-directory -C firmware

# The nbgrader course (notebooks/README.md): `make release` writes the student versions of
# the notebooks (nbgrader generate_assignment) and the templates of the student files
# (generated from solutions/) into notebooks/release/, proves that no solution text is in
# them, and packs out/task4-student-bundle.tar.gz.
.PHONY: release
release: setup
	@$(ENV) $(PY) -m hri_teleop.apps.course release

# Notebooks (notebooks/, one per handout exercise): JupyterLab with the "hri-teleop" kernel
# (.venv's Python in tools/env.sh's ROS shell, registered inside .venv); the widgets need
# no extension build (ipywidgets 8, ipympl). LAB_ARGS=... go to jupyter lab, e.g. --no-browser.
.PHONY: lab
lab: setup
	@$(ENV) $(PY) -m hri_teleop.apps.lab $(LAB_ARGS)
