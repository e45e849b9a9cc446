# The two commands a newcomer needs: `make run` and `make test`.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed-$(shell cat pyproject.toml constraints.txt | cksum | cut -d' ' -f1)
## The tested versions of every dependency, of pip and of the build backend (constraints.txt): pip reads
## PIP_CONSTRAINT for the install and for the isolated build of the package alike.
export PIP_CONSTRAINT := $(CURDIR)/constraints.txt

.PHONY: setup warm run serve test lint bench browser clean

$(STAMP): pyproject.toml constraints.txt
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[dev]'
	rm -f $(VENV)/.installed-*
	touch $(STAMP)

## After install: compile the sources to bytecode, then run each command once so that the first real
## run finds the simulation's numba kernels compiled (numba's cache), the catalog database and the unit
## factors already cached. A sizing needs no compiled code (its checks are numpy); `make warm` redoes
## the warm-up.
WARM := $(VENV)/.warm
$(WARM): $(STAMP)
	$(PY) -m compileall -q src >/dev/null
	$(VENV)/bin/drivetrain size examples/ball_screw.yaml >/dev/null || [ $$? -eq 1 ]
	$(VENV)/bin/drivetrain simulate examples/belt.yaml >/dev/null
	touch $(WARM)

setup: $(STAMP) $(WARM)

warm: $(STAMP)
	rm -f $(WARM)
	$(MAKE) $(WARM)

## Debian's Chromium and poppler-utils for the report and web-app browser tests (skipped when present).
## Installing them needs root or sudo; without either this stops with one line saying what to install.
browser:
	@need=""; command -v chromium >/dev/null 2>&1 || command -v chromium-browser >/dev/null 2>&1 || need=" chromium"; \
	command -v pdftoppm >/dev/null 2>&1 || need="$$need poppler-utils"; \
	[ -z "$$need" ] && exit 0; \
	if [ "$$(id -u)" = 0 ]; then sudo=""; elif command -v sudo >/dev/null 2>&1; then sudo="sudo"; \
	else echo "make browser: the browser tests need$$need, and installing it needs root or sudo (neither is available here): as an administrator run 'apt-get install$$need', then make test again" >&2; exit 1; fi; \
	$$sudo apt-get update -qq && $$sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq$$need >/dev/null

run: setup
	$(VENV)/bin/drivetrain size examples/ball_screw.yaml --report out/ball_screw.html

serve: setup
	$(VENV)/bin/drivetrain serve

lint: setup
	$(VENV)/bin/ruff check src tests bench scripts
	$(VENV)/bin/mypy

test: setup browser lint
	$(PY) -m pytest -n 2 -p no:cacheprovider

## wrk drives the web load benchmark (bench_web_load.py), leaving the cores to the server (skipped when present).
bench: setup
	@command -v wrk >/dev/null 2>&1 || \
	  { if [ "$$(id -u)" = 0 ]; then apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq wrk >/dev/null; \
	    else sudo apt-get update -qq && sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -qq wrk >/dev/null; fi; }
	$(PY) bench/run_all.py

clean:
	rm -rf $(VENV) out .pytest_cache .mypy_cache .ruff_cache
