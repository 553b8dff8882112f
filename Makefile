# kreisel: every routine command. `make demo` and `make test` set up a fresh machine
# themselves: a virtual environment in .venv, the Python dependencies, and the compiled
# extension in release mode.

PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
DEPS   := $(VENV)/.deps-installed
EXT    := $(VENV)/.ext-built
VENDOR       := python/kreisel/explore/static/vendor
VENDOR_STAMP := $(VENDOR)/.installed
RUST_SOURCES := $(shell find crates -name '*.rs' -o -name Cargo.toml) Cargo.toml pyproject.toml

# The extension is built for the machine that builds it: on an x86-64 CPU with AVX2 and FMA
# (x86-64-v3: Intel since 2013, AMD since 2015) the integrators' stage sums run four numbers
# wide, which takes 14 % of the instructions of a play-top run and 26 % of a heavy-top run.
# Elsewhere the portable baseline. Set KREISEL_RUSTFLAGS to choose (empty: baseline); an
# extension built this way must run on a CPU of the same level.
V3_FLAGS := avx avx2 bmi1 bmi2 f16c fma abm movbe xsave
KREISEL_RUSTFLAGS ?= $(shell [ "$$(uname -m)" = x86_64 ] && [ -r /proc/cpuinfo ] && \
	for f in $(V3_FLAGS); do grep -m1 '^flags' /proc/cpuinfo | grep -qw $$f || exit 0; done && \
	echo "-C target-cpu=x86-64-v3")

.PHONY: demo test test-rust test-python bench lint fmt clean setup fuzz fuzz-floor docs browser

setup: $(EXT) $(VENDOR_STAMP)

# The JavaScript of `kreisel explore`'s page (three.js, uPlot), pinned by web/package-lock.json:
# npm installs exactly those versions and the files the page loads are copied into the
# package (static/vendor, not in git). The page loads nothing from the network.
$(VENDOR_STAMP): web/package.json web/package-lock.json
	@command -v npm >/dev/null || { echo "installing Debian's npm (Node.js) for the page's JavaScript"; \
		apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq npm; }
	npm ci --prefix web --ignore-scripts --no-audit --no-fund --loglevel=error
	mkdir -p $(VENDOR)
	cp web/node_modules/three/build/three.module.min.js \
	   web/node_modules/three/examples/jsm/controls/OrbitControls.js \
	   web/node_modules/uplot/dist/uPlot.esm.js web/node_modules/uplot/dist/uPlot.min.css $(VENDOR)/
	cp web/node_modules/three/LICENSE $(VENDOR)/LICENSE-three
	cp web/node_modules/uplot/LICENSE $(VENDOR)/LICENSE-uplot
	touch $@

# The maths renderer of the documentation site, MathJax 3 (SVG output: no web fonts to load),
# pinned by web/package-lock.json like the page's JavaScript and copied next to the site's
# sources (docs/_vendor, not in git): the site renders every formula with no network.
DOCS_VENDOR       := docs/_vendor/mathjax
DOCS_VENDOR_STAMP := $(DOCS_VENDOR)/.installed
$(DOCS_VENDOR_STAMP): $(VENDOR_STAMP)
	mkdir -p $(DOCS_VENDOR)
	cp web/node_modules/mathjax/es5/tex-svg-full.js $(DOCS_VENDOR)/
	cp web/node_modules/mathjax/LICENSE $(DOCS_VENDOR)/LICENSE-mathjax
	touch $@

# The browser tests of `kreisel explore` drive Debian's Chromium headless (Selenium with
# Debian's chromedriver: no browser is downloaded at run time).
browser:
	@[ -x /usr/bin/chromium ] && [ -x /usr/bin/chromedriver ] || { \
		echo "installing Debian's chromium and chromium-driver for the browser tests"; \
		apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium chromium-driver; }

$(PY):
	$(PYTHON) -m venv $(VENV)

$(DEPS): pyproject.toml requirements-dev.txt | $(PY)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -r requirements-dev.txt
	touch $@

$(EXT): $(DEPS) $(RUST_SOURCES)
	@command -v cargo >/dev/null || { echo "cargo (Rust) is required: https://rustup.rs"; exit 1; }
	RUSTFLAGS="$(KREISEL_RUSTFLAGS)" $(VENV)/bin/maturin develop --release --quiet
	touch $@

demo: $(EXT) $(VENDOR_STAMP)
	$(VENV)/bin/kreisel demo

test: $(EXT) $(VENDOR_STAMP) browser test-rust test-python

test-rust:
	cargo test --quiet

test-python: $(EXT) $(VENDOR_STAMP) browser
	$(PY) -m pytest -q

# The property-based fuzz campaign (tests/fuzz): 10^5 calls of every public function with
# valid, boundary and hostile values, each in a worker process with a time limit; prints the
# counts by outcome and by function. `make test` runs a derandomised share of it.
FUZZ_CALLS ?= 100000
fuzz: $(EXT)
	$(PY) tests/fuzz/campaign.py --calls $(FUZZ_CALLS) --timeout 3

# The property-based campaign of floor runs (tests/fuzz/floor_campaign.py): random tops of 1 to
# 4 parts, every friction law, drops, spins, flat and upside-down starts; counts by outcome.
# `make test` runs a derandomised share of it (tests/test_floor_properties.py).
FLOOR_RUNS ?= 10000
fuzz-floor: $(EXT)
	$(PY) tests/fuzz/floor_campaign.py --runs $(FLOOR_RUNS) --seed 1 --timeout 20

bench: $(EXT)
	$(PY) -m pip install --quiet -r requirements-bench.txt
	$(PY) benchmarks/bench_exact.py
	$(PY) benchmarks/bench_simulate.py
	$(PY) benchmarks/bench_driven.py
	$(PY) benchmarks/bench_sensitivities.py
	$(PY) benchmarks/bench_mujoco.py
	$(PY) benchmarks/bench_play.py
	$(PY) benchmarks/bench_tippe_mujoco.py
	$(PY) benchmarks/bench_tippe_peg_mujoco.py
	$(PY) benchmarks/bench_euler_disk_mujoco.py
	$(PY) benchmarks/bench_sweep.py
	$(PY) benchmarks/bench_quantum.py

# The documentation site (docs/) into docs/_build/html: the guide, theory, API reference, the
# gallery (examples/, run at build time) and the tutorials (executed notebooks). Installing the
# tools needs PyPI; the build itself needs no network. Every Sphinx warning is an error.
DOCS_DEPS := $(VENV)/.docs-deps-installed
$(DOCS_DEPS): requirements-docs.txt | $(DEPS)
	$(PY) -m pip install --quiet -r requirements-docs.txt
	touch $@

docs: $(EXT) $(VENDOR_STAMP) $(DOCS_VENDOR_STAMP) $(DOCS_DEPS)
	MPLBACKEND=Agg $(VENV)/bin/sphinx-build -W --keep-going -b html docs docs/_build/html

lint: $(DEPS)
	cargo clippy --all-targets -- -D warnings
	cargo fmt --check
	$(VENV)/bin/ruff check python tests benchmarks examples
	$(VENV)/bin/ruff format --check python tests benchmarks examples
	$(VENV)/bin/mypy

fmt: $(DEPS)
	cargo fmt
	$(VENV)/bin/ruff format python tests benchmarks examples

clean:
	rm -rf $(VENV) target kreisel-out docs/_build docs/auto_examples docs/api/generated \
		web/node_modules $(VENDOR) docs/_vendor examples/kreisel-out
