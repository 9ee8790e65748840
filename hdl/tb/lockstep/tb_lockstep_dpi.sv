// Lockstep testbench in SystemVerilog with DPI-C (verification method 2, simulator-neutral
// variant of lockstep.cpp): reads the INPUT columns of a vector file, drives the DUT and steps
// the Rust reference model through pmu50_dpi.c every clock, and has the model compare (the one
// comparison of the C ABI, pmu50_check), in every cycle k:
//   - after rising edge k: the outputs and (unless PORTS_ONLY) the registers;
//   - the combinational internals of cycle k (before edge k+1) (unless PORTS_ONLY).
// This bench only feeds values, in the C ABI's index order (hdl/ffi/include/pmu50.h).
// The first divergence is reported with its tick (edge number; = time / T), the differing
// signals (model vs RTL) and the inputs of the last HISTORY ticks, then $fatal.
//
// Parameters: as tb_vectors.v (the reset values of the DUT and of the model come from them; the
// testbench checks them against the vector header). Plusargs: +vec=FILE; +coverage=FILE samples
// the functional coverage model at every step and writes FILE (coverage.json, verdict pass or
// fail) at the end, with run id +run_id=ID (default dpi/<vector file>).
// Run with Verilator: hdl/scripts/run_lockstep_dpi.sh FILE.vec (builds with --binary, one build per
// parameter set). Other simulators: compile this file, pmu50_dpi.c (-I hdl/ffi/include) and the
// design, link target/release/libpmu50_ffi.so (or .a), pass the parameters with -g/-G/-defparam.
// Define PORTS_ONLY for a design that does not have the twin's register/internals hierarchy.
// Timing (ns): rising edge k at k*T; in the middle of cycle k (k*T + T/2) the state after edge k
// is compared and the inputs of cycle k are applied (blocking: no race with the clock edge), 1 ns
// later the model takes its step and the internals are compared.
`timescale 1ns/1ns

module tb_lockstep_dpi;
    parameter int SYNC_DEPTH = 2;
    parameter int CNT_W      = 16;
    parameter int ADAPTIVE   = 1;
    parameter int PW         = 5;
    parameter int PI         = 12;
    parameter int PS         = 5;
    parameter int SI_MAX     = 660;
    parameter int SI_MIN     = 220;
    parameter int T1         = 220;
    parameter int T2         = 110;
    parameter int CTH        = 4;
    parameter int SMP_ON     = 10;
    parameter int CLOCK_NS   = 10000;
    parameter int HISTORY    = 8;

    localparam int T = CLOCK_NS;       // >= 8
    localparam int TH = T / 2;
    localparam int NOUT = 23;
    localparam int NREG = 26;
    localparam int NINT = 9;

    import "DPI-C" function chandle pmu50_dpi_new(input int sync_depth, input int cnt_width, input int adaptive,
        input int pw, input int pi, input int ps, input int si_max, input int si_min, input int t1, input int t2,
        input int cth, input int smp_on);
    import "DPI-C" function string pmu50_dpi_last_error();
    import "DPI-C" function void pmu50_dpi_free(input chandle h);
    import "DPI-C" function int pmu50_dpi_step(input chandle h, input int ig, input int vs2_ok, input int cmp_s,
        input int cmp_c, input int bus_we, input int bus_addr, input int bus_wdata);
    import "DPI-C" function int pmu50_dpi_check_sizes(input int n_outputs, input int n_regs, input int n_internals);
    import "DPI-C" function int pmu50_dpi_check_state(input chandle h, input longint outputs[NOUT],
        input longint regs[NREG], input int with_regs);
    import "DPI-C" function int pmu50_dpi_check_internals(input chandle h, input longint internals[NINT]);
    import "DPI-C" function string pmu50_dpi_check_report(input chandle h);
    import "DPI-C" function int pmu50_dpi_coverage_on(input chandle h, input longint clock_ns);
    import "DPI-C" function int pmu50_dpi_coverage_write(input chandle h, input string path, input string run_id,
        input string verdict);

    // ---- DUT
    logic        clk, rst_n;
    logic        ig, vs2_ok, cmp_s, cmp_c, bus_we;
    logic [7:0]  bus_addr;
    logic [15:0] bus_wdata;
    wire         sig, vr_hi, vm_en, vs1_en, vs2_en, vp_en, rail_hi, st, sr, ps_win, smp, cs, cc;
    wire [CNT_W-1:0] cnt_s, cnt_c;
    wire [7:0]   cnt_r;
    wire [15:0]  si;
    wire         hist_s, hist_c, diag, quadrant_skip;
    wire [15:0]  bus_rdata;
    wire         bus_err;

    pmu50 #(
        .SYNC_DEPTH(SYNC_DEPTH), .CNT_W(CNT_W), .ADAPTIVE(ADAPTIVE), .PW(PW), .PI(PI), .PS(PS),
        .SI_MAX(SI_MAX), .SI_MIN(SI_MIN), .T1(T1), .T2(T2), .CTH(CTH), .SMP_ON(SMP_ON)
    ) dut (.*);

    // the DUT's values in the C ABI's index order (hdl/ffi/include/pmu50.h): outputs, registers,
    // combinational internals
    task automatic rtl_outputs(output longint o [NOUT]);
        o = '{sig, vr_hi, vm_en, vs1_en, vs2_en, vp_en, rail_hi, st, sr, ps_win, smp, cs, cc, cnt_s, cnt_c,
              cnt_r, si, hist_s, hist_c, diag, quadrant_skip, bus_rdata, bus_err};
    endtask

`ifndef PORTS_ONLY
    task automatic rtl_regs(output longint r [NREG]);
        r = '{dut.action_switching.sync,
              dut.register_file.adaptive, dut.register_file.pw, dut.register_file.pi, dut.register_file.ps,
              dut.register_file.si_max, dut.register_file.si_min, dut.register_file.t1, dut.register_file.t2,
              dut.register_file.cth, dut.register_file.smp_on, dut.register_file.bus_err, dut.register_file.rdata,
              dut.timing_generator.tmr, dut.sensor_power_determination.sr,
              dut.comparator_latch.cs, dut.comparator_latch.cc, dut.comparator_latch.vld,
              dut.updown_counter.cnt_s, dut.updown_counter.cnt_c, dut.updown_counter.quadrant_skip,
              dut.drive_interval.si, dut.drive_interval.hist_s, dut.drive_interval.hist_c, dut.drive_interval.cnt_r,
              dut.count_diagnosis.diag};
    endtask

    task automatic rtl_internals(output longint x [NINT]);
        x = '{dut.internals.kon, dut.internals.koff, dut.internals.upd, dut.internals.first, dut.internals.chg_s,
              dut.internals.chg_c, dut.internals.skip_clr, dut.internals.fig17, dut.internals.fig18};
    endtask
`endif

    // ---- clock: rising edges at T, 2T, ...
    initial begin
        clk = 1'b0;
        #T;
        forever begin
            clk = 1'b1;
            #TH;
            clk = 1'b0;
            #(T - TH);
        end
    end

    chandle m;
    int fd, rc, k, nx, hval, c;
    longint rx [NINT];
    string vecfile, line, hname, covfile, run_id;
    logic [15:0] f [30];
    logic [71:0] hist [$];   // {edge, ig, vs2_ok, cmp_s, cmp_c, bus_we, bus_addr, bus_wdata, 11'(0)}

    task automatic fail_param(string n, int hv, int cv);
        $display("FAIL header: %s = %0d in the vector file, compiled with %0d", n, hv, cv);
        $fatal(1, "parameter mismatch");
    endtask

    // the parameters a vector header may name, and the values this build has
    localparam int NPARAM = 12;
    localparam string PARAM_NAMES [NPARAM] = '{"SYNC_DEPTH", "CNT_W", "ADAPTIVE", "PW", "PI", "PS", "SI_MAX",
                                                "SI_MIN", "T1", "T2", "CTH", "SMP_ON"};
    localparam int PARAM_VALUES [NPARAM] = '{SYNC_DEPTH, CNT_W, ADAPTIVE, PW, PI, PS, SI_MAX, SI_MIN, T1, T2,
                                              CTH, SMP_ON};

    task automatic check_param(string n, int v);
        for (int i = 0; i < NPARAM; i++)
            if (n == PARAM_NAMES[i] && v != PARAM_VALUES[i]) fail_param(n, v, PARAM_VALUES[i]);
    endtask

    function automatic bit read_line();
        rc = $fscanf(fd, "%h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h",
                     f[0], f[1], f[2], f[3], f[4], f[5], f[6], f[7], f[8], f[9],
                     f[10], f[11], f[12], f[13], f[14], f[15], f[16], f[17], f[18], f[19],
                     f[20], f[21], f[22], f[23], f[24], f[25], f[26], f[27], f[28], f[29]);
        return rc == 30;
    endfunction

    // the coverage file, when +coverage=FILE was given
    task automatic write_coverage(string verdict);
        if (covfile != "" && pmu50_dpi_coverage_write(m, covfile, run_id, verdict) != 0)
            $fatal(1, "coverage: %s", pmu50_dpi_last_error());
    endtask

    task automatic report_and_stop(int tick, string when);
        write_coverage("fail");
        $write("%s", pmu50_dpi_check_report(m));
        $display("LOCKSTEP FAIL %s: first divergence at tick %0d (%s), time %0t", vecfile, tick, when, $time);
        $display("last %0d ticks: edge | ig vs2_ok cmp_s cmp_c bus_we bus_addr bus_wdata (inputs sampled at that edge)", hist.size());
        foreach (hist[i])
            $display("  %8d | %0d %0d %0d %0d %0d %02h %04h", hist[i][71:40], hist[i][39], hist[i][38],
                     hist[i][37], hist[i][36], hist[i][35], hist[i][34:27], hist[i][26:11]);
        $fatal(1, "lockstep divergence");
    endtask

    // outputs and registers after edge `tick`
    task automatic compare_state(int tick);
        longint ro [NOUT];
        longint rr [NREG];
        int n;
        rtl_outputs(ro);
        for (int i = 0; i < NREG; i++) rr[i] = 0;
`ifndef PORTS_ONLY
        rtl_regs(rr);
        n = pmu50_dpi_check_state(m, ro, rr, 1);
`else
        n = pmu50_dpi_check_state(m, ro, rr, 0);
`endif
        if (n < 0) $fatal(1, "model: %s", pmu50_dpi_last_error());
        if (n > 0) report_and_stop(tick, "after the rising edge");
    endtask

    initial begin
        ig = 0; vs2_ok = 0; cmp_s = 0; cmp_c = 0; bus_we = 0; bus_addr = 0; bus_wdata = 0;
        rst_n = 1'b1;
        if (T < 8) $fatal(1, "CLOCK_NS must be at least 8");
        if (!$value$plusargs("vec=%s", vecfile)) $fatal(1, "usage: +vec=FILE.vec");
        fd = $fopen(vecfile, "r");
        if (fd == 0) $fatal(1, "cannot open %s", vecfile);
        // header
        c = $fgetc(fd);
        while (c == "/" || c == "\n" || c == " " || c == "\r") begin
            if (c == "/") begin
                rc = $fgets(line, fd);
                if ($sscanf(line, "/ param %s %d", hname, hval) == 2) check_param(hname, hval);
                else if ($sscanf(line, "/ clock_ns %d", hval) == 1 && hval != CLOCK_NS) fail_param("clock_ns", hval, CLOCK_NS);
            end
            c = $fgetc(fd);
        end
        if (c != -1) rc = $ungetc(c, fd);
        m = pmu50_dpi_new(SYNC_DEPTH, CNT_W, ADAPTIVE, PW, PI, PS, SI_MAX, SI_MIN, T1, T2, CTH, SMP_ON);
        if (m == null) $fatal(1, "model: %s", pmu50_dpi_last_error());
        if (pmu50_dpi_check_sizes(NOUT, NREG, NINT) != 0) $fatal(1, "NOUT/NREG/NINT differ from the C ABI's counts (pmu50.h)");
        covfile = "";
        if ($value$plusargs("coverage=%s", covfile)) begin
            if (!$value$plusargs("run_id=%s", run_id)) run_id = {"dpi/", vecfile};
            if (pmu50_dpi_coverage_on(m, CLOCK_NS) != 0) $fatal(1, "coverage: %s", pmu50_dpi_last_error());
        end

        // power-on reset pulse before the first edge
        #1 rst_n = 1'b0;
        #1 rst_n = 1'b1;
        #(TH - 2);

        k = 0;
        forever begin
            // middle of cycle k: the state after edge k is stable
            compare_state(k);
            if (!read_line()) break;
            {ig, vs2_ok, cmp_s, cmp_c, bus_we} = {f[0][0], f[1][0], f[2][0], f[3][0], f[4][0]};
            bus_addr = f[5][7:0];
            bus_wdata = f[6];
            hist.push_back({32'(k + 1), ig, vs2_ok, cmp_s, cmp_c, bus_we, bus_addr, bus_wdata, 11'd0});
            if (hist.size() > HISTORY) void'(hist.pop_front());
            #1;
            if (pmu50_dpi_step(m, ig, vs2_ok, cmp_s, cmp_c, bus_we, bus_addr, bus_wdata) != 0)
                $fatal(1, "model: %s", pmu50_dpi_last_error());
`ifndef PORTS_ONLY
            rtl_internals(rx);
            nx = pmu50_dpi_check_internals(m, rx);
            if (nx < 0) $fatal(1, "model: %s", pmu50_dpi_last_error());
            if (nx > 0) report_and_stop(k, "combinational, before the next rising edge");
`endif
            #(T - 1);
            k++;
        end
        $display("PASS ticks=%0d outputs=%0d registers=%0d internals=%0d", k, NOUT, NREG, NINT);
        write_coverage("pass");
        if (covfile != "") $display("coverage: %s (run %s)", covfile, run_id);
        pmu50_dpi_free(m);
        $finish;
    end
endmodule
