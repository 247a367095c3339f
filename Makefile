# Two entry points (see README): `make report` and `make test`. Both set up .venv first.
PROBES ?= $(if $(VALIDATE_PROBES),$(VALIDATE_PROBES),../shared/probes)
# a checkout alone (no ../shared beside it) runs on the built-in environments: nothing points at a missing folder
PROBES_ARG := $(if $(wildcard $(PROBES)),--probes $(PROBES),)
PROBES_ENV := $(if $(wildcard $(PROBES)),VALIDATE_PROBES=$(PROBES),)

.PHONY: setup report quick test test-slow lint bench

setup:
	bash scripts/setup.sh

# the full report on two Dask worker processes (the 2-core machine's second core; results.json is the same number
# for number as --workers 1 but for one Mitsuba render's float-atomic order, see docs/scale.md); WORKERS=1 runs serially
WORKERS ?= 2

report: setup
	.venv/bin/python -m validate all --workers $(WORKERS) $(PROBES_ARG)

quick: setup
	.venv/bin/python -m validate all --quick $(PROBES_ARG)

# two pytest workers (pytest-xdist), a test file per worker: the 2-core machine's second core is otherwise idle
# while a test waits on a subprocess, Node or the browser; a crashed worker ends the run (no restart: after a
# restart pytest-xdist's loadfile scheduler was seen to wait forever for the crashed file's tests)
test: setup
	$(PROBES_ENV) .venv/bin/python -m pytest -q -n 2 --dist loadfile --max-worker-restart 0

test-slow: setup
	$(PROBES_ENV) .venv/bin/python -m pytest -q -m slow

lint:
	.venv/bin/ruff check validate tests
	.venv/bin/lint-imports

bench: setup
	.venv/bin/python -m validate bench
