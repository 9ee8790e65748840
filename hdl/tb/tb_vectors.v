// Vector replay testbench (verification method 1), Icarus Verilog (Verilog-2005 + $fscanf).
//
// Reads a vector file written by `pmu50 vectors SCENARIO -o FILE.vec` (docs/spec.md 6.2):
// header lines `// ...`, then one line per tick with 30 hex fields: 7 inputs, then the 23
// outputs expected after the edge. Line k (0-based) holds the inputs of edge k+1 (applied at
// time k*T) and the outputs expected after that edge (visible at time (k+1)*T).
//
// Parameters (compile time, from the header `// param NAME VALUE` / `// clock_ns N` lines):
//   iverilog -P tb_vectors.SI_MAX=660 ... -P tb_vectors.CLOCK_NS=10000
// (hdl/scripts/run_vectors.sh extracts them). The testbench checks them against the header.
// Plusargs: +vec=FILE (required), +vcd=FILE (optional waveform), +nocheck (replay the inputs
// only, no comparison: a clean waveform for `pmu50 diff`, method 3), +verdict=FILE (the
// MISMATCH and PASS lines also go to FILE, which the RTL's own $display cannot reach).
//
// Port contract: the bench reads the DUT's ports only. Defines: TB_DUT_INST (the instance comes
// from tb_dut_inst.vh, for a top that lacks some parameters), TB_TWIN_INTERNALS (the twin's
// scope `internals` is frozen at the last edge, for the waveform diff of the twin's VCD).
//
// Time convention (spec 6.1): rising edge k at k*T; inputs for edge k+1 driven with
// non-blocking assignments at edge k (time 0 for the first); outputs compared at the falling
// edge after each rising edge. Timescale 1 us (the model's default), or 1 ns when compiled with
// -DTB_TIMESCALE_NS (clock periods that are not an even number of microseconds).
//
// Result: `PASS ticks=<n>` or, at the first tick with a difference, one line per differing
// output `MISMATCH tick=<k> signal=<name> expected=<hex> got=<hex>` followed by `FAIL ...` and
// $fatal (vvp exits non-zero). tick = edge number = time / T, the same numbering as the
// lockstep testbench and `pmu50 diff` (time of the first difference).
// Under Verilator the precision is finer: its bench steps a thousandth of a unit (below).
`ifdef TB_TIMESCALE_NS
`ifdef VERILATOR
`timescale 1ns/1ps
`else
`timescale 1ns/1ns
`endif
`else
`ifdef VERILATOR
`timescale 1us/1ns
`else
`timescale 1us/1us
`endif
`endif

module tb_vectors;
    // ---- parameters of the run (must equal the header)
    parameter integer SYNC_DEPTH = 2;
    parameter integer CNT_W      = 16;
    parameter integer ADAPTIVE   = 1;
    parameter integer PW         = 5;
    parameter integer PI         = 12;
    parameter integer PS         = 5;
    parameter integer SI_MAX     = 660;
    parameter integer SI_MIN     = 220;
    parameter integer T1         = 220;
    parameter integer T2         = 110;
    parameter integer CTH        = 4;
    parameter integer SMP_ON     = 10;
    parameter integer CLOCK_NS   = 10000;

`ifdef TB_TIMESCALE_NS
    localparam integer T  = CLOCK_NS;
    localparam [15:0] TUNIT = "ns";
`else
    localparam integer T  = CLOCK_NS / 1000;
    localparam [15:0] TUNIT = "us";
`endif
    localparam integer TH = (T / 2 > 0) ? T / 2 : 1;   // clock high time
    localparam integer NIN  = 7;
    localparam integer NOUT = 23;

    // ---- DUT
    reg         clk;
    reg         rst_n;
    reg         ig, vs2_ok, cmp_s, cmp_c, bus_we;
    reg  [7:0]  bus_addr;
    reg  [15:0] bus_wdata;
    wire        sig, vr_hi, vm_en, vs1_en, vs2_en, vp_en, rail_hi, st, sr, ps_win, smp, cs, cc;
    wire [CNT_W-1:0] cnt_s, cnt_c;
    wire [7:0]  cnt_r;
    wire [15:0] si;
    wire        hist_s, hist_c, diag, quadrant_skip;
    wire [15:0] bus_rdata;
    wire        bus_err;

`ifdef TB_DUT_INST
    // An RTL whose top lacks some parameters (a netlist has none): the runner writes the
    // instance with the parameters the top has (src/regress/dut/icarus.rs).
    `include "tb_dut_inst.vh"
`else
    pmu50 #(
        .SYNC_DEPTH(SYNC_DEPTH), .CNT_W(CNT_W), .ADAPTIVE(ADAPTIVE), .PW(PW), .PI(PI), .PS(PS),
        .SI_MAX(SI_MAX), .SI_MIN(SI_MIN), .T1(T1), .T2(T2), .CTH(CTH), .SMP_ON(SMP_ON)
    ) dut (
        .clk(clk), .rst_n(rst_n),
        .ig(ig), .vs2_ok(vs2_ok), .cmp_s(cmp_s), .cmp_c(cmp_c),
        .bus_we(bus_we), .bus_addr(bus_addr), .bus_wdata(bus_wdata),
        .sig(sig), .vr_hi(vr_hi), .vm_en(vm_en), .vs1_en(vs1_en), .vs2_en(vs2_en),
        .vp_en(vp_en), .rail_hi(rail_hi), .st(st), .sr(sr), .ps_win(ps_win), .smp(smp),
        .cs(cs), .cc(cc), .cnt_s(cnt_s), .cnt_c(cnt_c), .cnt_r(cnt_r), .si(si),
        .hist_s(hist_s), .hist_c(hist_c), .diag(diag), .quadrant_skip(quadrant_skip),
        .bus_rdata(bus_rdata), .bus_err(bus_err)
    );
`endif

    // ---- outputs as an indexable list (column order of the vector file)
    reg [16*8-1:0] oname [0:NOUT-1];
    initial begin
        oname[0]  = "sig";     oname[1]  = "vr_hi";  oname[2]  = "vm_en";   oname[3]  = "vs1_en";
        oname[4]  = "vs2_en";  oname[5]  = "vp_en";  oname[6]  = "rail_hi"; oname[7]  = "st";
        oname[8]  = "sr";      oname[9]  = "ps_win"; oname[10] = "smp";     oname[11] = "cs";
        oname[12] = "cc";      oname[13] = "cnt_s";  oname[14] = "cnt_c";   oname[15] = "cnt_r";
        oname[16] = "si";      oname[17] = "hist_s"; oname[18] = "hist_c";  oname[19] = "diag";
        oname[20] = "quadrant_skip"; oname[21] = "bus_rdata"; oname[22] = "bus_err";
    end

    // actual outputs, 16 bits per column (cnt_s, cnt_c zero-extended from CNT_W)
    wire [16*NOUT-1:0] act_vec = {
        15'd0, sig,    15'd0, vr_hi,  15'd0, vm_en,   15'd0, vs1_en, 15'd0, vs2_en, 15'd0, vp_en,
        15'd0, rail_hi, 15'd0, st,    15'd0, sr,      15'd0, ps_win, 15'd0, smp,    15'd0, cs,
        15'd0, cc,
        {(16 - CNT_W){1'b0}}, cnt_s,  {(16 - CNT_W){1'b0}}, cnt_c,
        8'd0, cnt_r,   si,            15'd0, hist_s,  15'd0, hist_c, 15'd0, diag,
        15'd0, quadrant_skip,         bus_rdata,      15'd0, bus_err };

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

    // ---- vector file
    integer    fd, vd, rc, c, i, k, nfail, hval, hticks, nocheck;
    reg [8*1024-1:0] vecfile, vcdfile, verdictfile;
    // A header line is read up to 255 characters (Verilator's string limit); the rest of a longer
    // one (a long scenario name) is skipped: the lines the bench parses are short.
    reg [8*255-1:0]  line;
    reg [8*64-1:0]   hname;
    reg [15:0] f [0:NIN+NOUT-1];     // current line
    reg [16*NOUT-1:0] ex_vec;        // expected outputs after the current edge
    reg        have_line;
    reg        fz_kon, fz_koff, fz_upd, fz_first, fz_chg_s, fz_chg_c, fz_skip_clr;
    reg [2:0]  fz_fig17, fz_fig18;

    task fail_header;
        input [8*64-1:0] what;
        input integer header_value;
        input integer compiled_value;
        begin
            $display("FAIL header: %0s = %0d in the vector file, but the testbench was compiled with %0d (pass -P tb_vectors.<NAME>=<value>)",
                     what, header_value, compiled_value);
            $fatal(1, "parameter mismatch");
        end
    endtask

    task check_param;
        input [8*64-1:0] n;
        input integer v;
        begin
            if      (n == "SYNC_DEPTH") begin if (v != SYNC_DEPTH) fail_header(n, v, SYNC_DEPTH); end
            else if (n == "CNT_W")      begin if (v != CNT_W)      fail_header(n, v, CNT_W); end
            else if (n == "ADAPTIVE")   begin if (v != ADAPTIVE)   fail_header(n, v, ADAPTIVE); end
            else if (n == "PW")         begin if (v != PW)         fail_header(n, v, PW); end
            else if (n == "PI")         begin if (v != PI)         fail_header(n, v, PI); end
            else if (n == "PS")         begin if (v != PS)         fail_header(n, v, PS); end
            else if (n == "SI_MAX")     begin if (v != SI_MAX)     fail_header(n, v, SI_MAX); end
            else if (n == "SI_MIN")     begin if (v != SI_MIN)     fail_header(n, v, SI_MIN); end
            else if (n == "T1")         begin if (v != T1)         fail_header(n, v, T1); end
            else if (n == "T2")         begin if (v != T2)         fail_header(n, v, T2); end
            else if (n == "CTH")        begin if (v != CTH)        fail_header(n, v, CTH); end
            else if (n == "SMP_ON")     begin if (v != SMP_ON)     fail_header(n, v, SMP_ON); end
            else if (n == "CLOCK_US")   begin if (v * 1000 != CLOCK_NS) fail_header(n, v, CLOCK_NS / 1000); end
            else $display("WARNING: unknown header parameter %0s", n);
        end
    endtask

    // Read the next data line into f[]; have_line = 0 at end of file.
    task read_line;
        begin
            rc = $fscanf(fd, "%h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h %h",
                         f[0], f[1], f[2], f[3], f[4], f[5], f[6], f[7], f[8], f[9],
                         f[10], f[11], f[12], f[13], f[14], f[15], f[16], f[17], f[18], f[19],
                         f[20], f[21], f[22], f[23], f[24], f[25], f[26], f[27], f[28], f[29]);
            if (rc == NIN + NOUT) have_line = 1'b1;
            else if (rc <= 0)     have_line = 1'b0;
            else begin
                $display("FAIL vector line %0d: %0d fields, expected %0d", k, rc, NIN + NOUT);
                $fatal(1, "bad vector file");
            end
        end
    endtask

    initial begin
        // inputs idle until the first line is read (all at time 0)
        ig = 1'b0; vs2_ok = 1'b0; cmp_s = 1'b0; cmp_c = 1'b0;
        bus_we = 1'b0; bus_addr = 8'd0; bus_wdata = 16'd0;
        // power-on reset: asserted at time 0 (after every process has started), released at
        // time 1 (before the first rising edge at T >= 2)
        rst_n = 1'b1;
`ifdef VERILATOR
        // No #0 in Verilator 5 (--timing): the falling edge a thousandth of a time unit later.
        #0.001 rst_n = 1'b0;
`else
        #0 rst_n = 1'b0;
`endif

        nocheck = $test$plusargs("nocheck");
        if (!$value$plusargs("vec=%s", vecfile)) begin
            $display("FAIL usage: vvp tb_vectors.vvp +vec=FILE.vec [+vcd=FILE.vcd]");
            $fatal(1, "no vector file");
        end
        fd = $fopen(vecfile, "r");
        if (fd == 0) begin
            $display("FAIL cannot open %0s", vecfile);
            $fatal(1, "no vector file");
        end
        // +verdict=FILE: the verdict lines also go to FILE, a channel the RTL cannot print on
        vd = 0;
        if ($value$plusargs("verdict=%s", verdictfile)) begin
            vd = $fopen(verdictfile, "w");
            if (vd == 0) begin
                $display("FAIL cannot write %0s", verdictfile);
                $fatal(1, "no verdict file");
            end
        end
        if ($value$plusargs("vcd=%s", vcdfile)) begin
            $dumpfile(vcdfile);
            $dumpvars(0, tb_vectors.dut);
        end

        // header
        hticks = -1;
        k = 0;
        c = $fgetc(fd);
        while (c == "/" || c == "\n" || c == " " || c == "\r") begin
            if (c == "/") begin
                line = 0;
                rc = $fgets(line, fd);
                if (rc == 255 && line[7:0] != "\n") begin
                    c = $fgetc(fd);
                    while (c != "\n" && c != -1) c = $fgetc(fd);
                end
                if ($sscanf(line, "/ param %s %d", hname, hval) == 2) check_param(hname, hval);
                else if ($sscanf(line, "/ clock_ns %d", hval) == 1) begin
                    if (hval != CLOCK_NS) fail_header("clock_ns", hval, CLOCK_NS);
                end
                else if ($sscanf(line, "/ ticks %d", hval) == 1) hticks = hval;
                else if ($sscanf(line, "/ fields %d", hval) == 1) begin
                    if (hval != NIN + NOUT) fail_header("fields", hval, NIN + NOUT);
                end
            end
            c = $fgetc(fd);
        end
        if (c != -1) rc = $ungetc(c, fd);

        read_line;
        if (!have_line) begin
            $display("FAIL %0s: no vector lines", vecfile);
            $fatal(1, "empty vector file");
        end
        // inputs of edge 1, at time 0
        {ig, vs2_ok, cmp_s, cmp_c, bus_we} = {f[0][0], f[1][0], f[2][0], f[3][0], f[4][0]};
        bus_addr  = f[5][7:0];
        bus_wdata = f[6];
        #1 rst_n = 1'b1;

        nfail = 0;
        while (have_line) begin
            ex_vec = {f[7],  f[8],  f[9],  f[10], f[11], f[12], f[13], f[14], f[15], f[16], f[17], f[18],
                      f[19], f[20], f[21], f[22], f[23], f[24], f[25], f[26], f[27], f[28], f[29]};
            @(posedge clk);                      // edge k+1
            k = k + 1;
            read_line;                           // inputs of the next edge
`ifdef TB_TWIN_INTERNALS
            if (!have_line) begin
                // Last edge: there are no inputs for the cycle after it. The model's VCD holds
                // the internals of the last cycle at the final time stamp, so freeze the twin's
                // (they still have their pre-edge values here: the NBA region has not run).
                fz_kon = dut.internals.kon;   fz_koff = dut.internals.koff; fz_upd = dut.internals.upd;
                fz_first = dut.internals.first; fz_chg_s = dut.internals.chg_s;
                fz_chg_c = dut.internals.chg_c; fz_skip_clr = dut.internals.skip_clr;
                fz_fig17 = dut.internals.fig17; fz_fig18 = dut.internals.fig18;
                force dut.internals.kon = fz_kon;       force dut.internals.koff = fz_koff;
                force dut.internals.upd = fz_upd;       force dut.internals.first = fz_first;
                force dut.internals.chg_s = fz_chg_s;   force dut.internals.chg_c = fz_chg_c;
                force dut.internals.skip_clr = fz_skip_clr;
                force dut.internals.fig17 = fz_fig17;   force dut.internals.fig18 = fz_fig18;
            end
`endif
`ifdef VERILATOR
            // The scheduler of Verilator 5.0 may commit this process's NBAs before the twin's
            // clocked blocks run: drive the next inputs a thousandth of a time unit after the edge.
            #0.001;
`endif
            if (have_line) begin
                ig        <= f[0][0];
                vs2_ok    <= f[1][0];
                cmp_s     <= f[2][0];
                cmp_c     <= f[3][0];
                bus_we    <= f[4][0];
                bus_addr  <= f[5][7:0];
                bus_wdata <= f[6];
            end
            @(negedge clk);                      // outputs after edge k settled
            if (!nocheck && act_vec !== ex_vec) begin
                for (i = 0; i < NOUT; i = i + 1) begin
                    if (act_vec[16*(NOUT-1-i) +: 16] !== ex_vec[16*(NOUT-1-i) +: 16]) begin
                        $display("MISMATCH tick=%0d signal=%0s expected=%0h got=%0h", k, oname[i],
                                 ex_vec[16*(NOUT-1-i) +: 16], act_vec[16*(NOUT-1-i) +: 16]);
                        if (vd != 0) $fdisplay(vd, "MISMATCH tick=%0d signal=%0s expected=%0h got=%0h", k, oname[i],
                                               ex_vec[16*(NOUT-1-i) +: 16], act_vec[16*(NOUT-1-i) +: 16]);
                        nfail = nfail + 1;
                    end
                end
                $display("FAIL %0s: first difference at tick %0d (after rising edge %0d, time %0t %0s; vector line %0d)",
                         vecfile, k, k, $time - TH, TUNIT, k - 1);
                if (vd != 0) $fclose(vd);
                $fatal(1, "vector mismatch");
            end
        end
        if (hticks >= 0 && hticks != k) begin
            $display("FAIL %0s: %0d vector lines, header says ticks %0d", vecfile, k, hticks);
            $fatal(1, "truncated vector file");
        end
        if (nocheck) $display("DONE ticks=%0d (inputs replayed, outputs not checked)", k);
        else         $display("PASS ticks=%0d", k);
        if (vd != 0) begin
            $fdisplay(vd, "PASS ticks=%0d", k);
            $fclose(vd);
        end
        $fclose(fd);
        $finish;
    end
endmodule
