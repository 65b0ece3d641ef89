# stiction — one entry point for people and CI. `make demo` and `make test` each set up
# everything they need (a virtual environment in .venv with the package built in release mode).
VENV   := .venv
PY     := $(VENV)/bin/python
OUT    := out
EXAMPLE ?= examples/msl/CoupledClutches.toml
# what the demo plots: speeds on one axes, the clutch modes on another
DEMO_SIGNALS ?= J1.w+J2.w+J3.w+J4.w,clutch1.mode+clutch2.mode+clutch3.mode

.PHONY: fmu-windows setup demo test test-fast test-rust test-python lint docs bench bench-io bench-fmu bench-scaling bench-sweep bench-stiff bench-interrupt soak clean

setup:
	@test -x $(PY) || python3 -m venv $(VENV)
	@$(PY) -m pip install --quiet --upgrade pip maturin
	@# the FMU runtime (a C-ABI library, not the extension module maturin builds) goes into the
	@# package next to _core, so that a wheel built after it ships it too
	@cargo build --release --quiet -p stiction-fmi
	@cp target/release/libstiction_fmi.so python/stiction/
	@VIRTUAL_ENV=$(CURDIR)/$(VENV) $(VENV)/bin/maturin develop --release --extras test --quiet

demo: setup
	@mkdir -p $(OUT)
	$(VENV)/bin/stiction simulate $(EXAMPLE) -o $(OUT)/$(basename $(notdir $(EXAMPLE))).csv \
		--plot $(OUT)/$(basename $(notdir $(EXAMPLE))).png --signals "$(DEMO_SIGNALS)"

# Everything: the Rust tests, then every Python test (tests/ mirrors python/stiction; see
# tests/conftest.py). The Rust test binaries take about 4 minutes to build the first time.
test: setup test-rust test-python

# The Python tests less those marked slow (`pytest -m slow --collect-only` lists them: the
# 1000-element models, the wheel build, the longest runs): well under a minute after setup.
# No Rust tests: they run in seconds, but building them the first time takes minutes.
test-fast: setup
	$(PY) -m pytest -q -m "not slow"

test-rust:
	cargo test --release -p stiction-core -p stiction-fmi

test-python:
	$(PY) -m pytest -q

lint: setup
	$(PY) scripts/check_structure.py
	$(PY) scripts/generate.py --check
	cargo fmt --all --check
	cargo clippy --release --all-targets -- -D warnings
	$(VENV)/bin/ruff check python tests scripts docs examples
	$(VENV)/bin/ruff format --check python tests scripts docs examples
	@# the Python package's layers and the one way in for optional packages (.importlinter)
	$(VENV)/bin/lint-imports --no-cache
	@# the compiled module against its stub (run outside the tree: stubtest imports by name)
	cd /tmp && $(CURDIR)/$(PY) -m mypy.stubtest stiction._core

# The documentation site in docs/_build/html: runs every example into the gallery and the
# tutorial's script; any warning (a broken example, a stale name, a bad docstring) fails it.
docs: setup
	@$(PY) -m pip install --quiet -r docs/requirements.txt
	$(PY) -m sphinx -W --keep-going -q -b html docs docs/_build/html

# The property tests over 10⁴ random drivetrains (CI runs a fixed budget of about 200).
soak: setup
	STICTION_SOAK=10000 $(PY) -m pytest -q tests/properties/test_properties.py tests/properties/test_mixed_drivetrains.py --hypothesis-show-statistics

bench: setup
	$(VENV)/bin/stiction bench

clean:
	rm -rf $(VENV) $(OUT) target docs/_build docs/_generated

# The FMU runtime for Windows x86-64, cross-compiled (docs/fmu.md, "Platforms"): every FMU
# exported afterwards carries it beside the Linux one. Not part of `test`: the Rust target is a
# download (rustup), the linker Debian's MinGW-w64.
fmu-windows:
	rustup target add x86_64-pc-windows-gnu
	command -v x86_64-w64-mingw32-gcc >/dev/null || apt-get install -y gcc-mingw-w64-x86-64
	CARGO_TARGET_DIR=target/cross CARGO_TARGET_X86_64_PC_WINDOWS_GNU_LINKER=x86_64-w64-mingw32-gcc \
		cargo build --release -p stiction-fmi --target x86_64-pc-windows-gnu

# Modelica import and result-file speed (issue 11): prints numbers, asserts nothing
bench-io: setup
	$(PY) scripts/bench_modelica_io.py

# FMU runtime speed and memory in a C host, and FMPy end to end (issue 12): prints numbers
bench-fmu: setup
	$(PY) scripts/bench_fmu.py

# Growth with model size (issue 10): chains and ladders of generated models; prints numbers
bench-scaling: setup
	$(PY) scripts/bench_scaling.py

# Sweeps (issue 9): 10⁴ CoupledClutches variants on 1 worker and every core, then the peak
# memory of metrics-only sweeps of 10³–5·10⁴ variants; prints numbers
bench-sweep: setup
	$(VENV)/bin/stiction bench --sweep 10000
	$(PY) scripts/bench_sweep_memory.py

# Solvers on stiff drivetrains (issue 13): tsit45, bdf, esdirk34, auto on examples/stiff and HeatLosses.
bench-stiff: setup
	$(VENV)/bin/stiction bench --stiff

# Ctrl-C latency (issue 13): a run, a cancel from another thread, a sweep and the CLI, each
# interrupted mid-run; prints min / median / max milliseconds (goal 0.2 s)
bench-interrupt: setup
	$(PY) scripts/bench_interrupt.py
