# Two entry points (see README): `make report` and `make test`. Both set up .venv first.
PROBES ?= $(if $(VALIDATE_PROBES),$(VALIDATE_PROBES),../shared/probes)
PROBES_ARG := $(if $(wildcard $(PROBES)),--probes $(PROBES),)

.PHONY: setup report quick test test-slow lint bench

setup:
	bash scripts/setup.sh

report: setup
	.venv/bin/python -m validate all $(PROBES_ARG)

quick: setup
	.venv/bin/python -m validate all --quick $(PROBES_ARG)

test: setup
	VALIDATE_PROBES=$(PROBES) .venv/bin/python -m pytest -q

test-slow: setup
	VALIDATE_PROBES=$(PROBES) .venv/bin/python -m pytest -q -m slow

lint:
	.venv/bin/ruff check validate tests
	.venv/bin/lint-imports

bench: setup
	.venv/bin/python -m validate bench
