# PMU 50 reference model. A fresh machine needs only the Rust toolchain: every target installs
# what it needs. `make run` and `make test` are the two commands of the README.

CARGO     ?= cargo
BIN       := target/release/pmu50
SCENARIOS := $(sort $(wildcard scenarios/*.toml))
SCENARIO  ?= fig15a

# Debian packages the tests use, as "command:package".
TOOLS := vcd2lxt2:gtkwave xvfb-run:xvfb xauth:xauth iverilog:iverilog verilator:verilator yosys:yosys

.PHONY: run test deps view golden bench cosim lint clean

## Install the Debian packages the tests need, when missing (needs root, as on CI).
deps:
	@missing=""; for t in $(TOOLS); do command -v $${t%%:*} >/dev/null 2>&1 || missing="$$missing $${t##*:}"; done; \
	if [ -n "$$missing" ]; then \
	  echo "installing Debian packages:$$missing"; \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $$missing >/dev/null; \
	fi

$(BIN): FORCE
	$(CARGO) build --release --bin pmu50

FORCE:

## Run every shipped scenario: vcd_out/<name>.vcd, .gtkw and .log, and a summary each.
run: $(BIN)
	$(BIN) run $(SCENARIOS) --out-dir vcd_out --log

## Everything: unit, property, golden and system tests of all crates, then HDL co-simulation.
test: deps
	$(CARGO) test --workspace
	$(MAKE) cosim

## Open one scenario in GTKWave with its save file: make view SCENARIO=fig15a
view: $(BIN) deps
	$(BIN) run scenarios/$(SCENARIO).toml --out-dir vcd_out
	gtkwave vcd_out/$(SCENARIO).vcd vcd_out/$(SCENARIO).gtkw

## Review changed golden snapshots (golden/*.snap) one by one.
golden:
	@command -v cargo-insta >/dev/null 2>&1 || $(CARGO) install cargo-insta --locked
	-INSTA_UPDATE=new $(CARGO) test --test golden
	$(CARGO) insta review --workspace

## Speed, side by side in one table: readable model, fast kernel, Verilator (-O3, --trace), the
## Rust tracer (VCD, FST), Icarus; park figures (docs/performance.md). Criterion micro-benchmarks
## of the simulator: cargo bench --bench sim_speed.
bench: deps
	bash benches/compare.sh

## HDL twin against the model: vectors (Icarus), lockstep (Verilator DPI-C), VCD diff, mutants.
cosim: deps $(BIN)
	bash hdl/cosim.sh

lint:
	$(CARGO) clippy --workspace --all-targets -- -D warnings

clean:
	$(CARGO) clean
	rm -rf vcd_out/*.vcd vcd_out/*.gtkw vcd_out/*.log hdl/build
