# The two commands a newcomer runs are `make demo` and `make test`; both set up first.
SHELL := /bin/bash
ENV := . tools/env.sh &&
PY := .venv/bin/python
# Headless pygame everywhere we run without a screen.
export SDL_VIDEODRIVER ?= dummy
export SDL_AUDIODRIVER ?= dummy
export PYGAME_HIDE_SUPPORT_PROMPT := 1

.PHONY: setup demo demo-sensor test lint clean

setup:
	@bash tools/setup.sh

# The whole lab simulated: teleoperation.launch sim:=true with the default scenario (~25 s).
demo: setup
	@$(ENV) $(PY) -m hri_teleop.ros.teleop_demo $(DEMO_ARGS)

# Only the sensor stage (handout Ex. 6): sensor.launch with the simulated press profile.
demo-sensor: setup
	@$(ENV) $(PY) -m hri_teleop.ros.sensor_demo

test: setup
	@$(ENV) $(PY) -m pytest -q -p no:cacheprovider $(PYTEST_ARGS)

lint: setup
	@$(ENV) catkin_lint --offline -W2 --strict hri_lab

clean:
	rm -rf .venv build out .pytest_cache .hypothesis
