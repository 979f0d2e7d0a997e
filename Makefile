# The set-up commands of the README: `make demo` and `make test`.
# Both create .venv with the machine's python3 and install delkit with every extra (`.[all]`) plus the
# test and docs tools. `make test-core` checks the light install: `pip install .` (no extras) in a fresh
# venv, its size, the core's tests and a plan + check + smcdel + draw there (bench/packaging.py).
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed
PYTEST_WORKERS ?= 2
CORE_VENV ?= build/core-venv

.PHONY: demo test test-slow test-core docs bench lint install clean browser

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[all,test,docs]'
	touch $(STAMP)

# the browser tests of delkit view (tests/view) use Debian's chromium + chromium-driver; installed here where
# apt-get works (root), otherwise those tests skip and say why
browser:
	@if command -v chromium >/dev/null && command -v chromedriver >/dev/null; then :; \
	elif [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	  (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium chromium-driver) \
	  >/dev/null 2>&1 || echo "make: could not install chromium with apt-get; the browser tests will skip"; \
	else echo "make: chromium/chromedriver not installed and apt-get not usable; the browser tests will skip"; fi

install: $(STAMP)

demo: $(STAMP)
	$(VENV)/bin/delkit demo

test: $(STAMP) browser
	$(PY) -m pytest -q -n $(PYTEST_WORKERS) -m "not slow"

test-slow: $(STAMP)
	$(PY) -m pytest -q -n $(PYTEST_WORKERS) -m slow

# the bare `pip install .` in a fresh venv (built from the wheels pip has cached or can reach)
test-core: $(STAMP)
	$(PY) bench/packaging.py --venv $(CORE_VENV) --python $(PYTHON)

# the API reference, generated from the docstrings (pdoc) into build/api; fails on any pdoc warning
docs: $(STAMP)
	$(PY) docs/api.py --out build/api

lint: $(STAMP)
	$(VENV)/bin/ruff check delkit planners sim arms tests bench

bench: $(STAMP)
	for b in bench/*.py; do $(PY) $$b || exit 1; done

clean:
	rm -rf $(VENV) build *.egg-info .pytest_cache
