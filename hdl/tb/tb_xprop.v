// X-propagation bench (`pmu50 xprop`, docs/verification.md "X-propagation"): the contract top
// `pmu50` in a 4-state simulation (Icarus) replaying a vector file (docs/spec.md 6.2), with every
// input X during reset and X at each tick the contract lets it float:
//   bus_wdata      while bus_we is 0 (a write is the only use of the data, spec 2.8);
//   cmp_s, cmp_c   while smp & sr is 0 (the latches take the comparators only then, spec 2.4).
// After reset, every output is checked after every edge: the first X or Z bit of each output is
// printed as `XPROP_X tick=<k> out=<name> value=<bits>`; `XPROP_DONE ticks=<n>` at the end.
//
//   iverilog -g2012 -P tb_xprop.<PARAM>=<value>... -o sim tb_xprop.v <RTL>; vvp -n sim +vec=FILE
`timescale 1ns/1ns
module tb_xprop;
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

    localparam integer NOUT = 23;

    reg         clk, rst_n;
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

    reg reported [0:NOUT-1];
    integer tick, fd, rc, k;
    reg [8*1024-1:0] vecfile;
    reg [8*512-1:0]  line;
    reg [15:0] a0, a1, a2, a3, a4, a5, a6;

    task check;
        input integer i;
        input [8*16-1:0] name;
        input [15:0] value;
        begin
            if (^value === 1'bx && !reported[i]) begin
                reported[i] = 1'b1;
                $display("XPROP_X tick=%0d out=%0s value=%b", tick, name, value);
            end
        end
    endtask

    task check_all;
        begin
            check(0, "sig", sig);         check(1, "vr_hi", vr_hi);     check(2, "vm_en", vm_en);
            check(3, "vs1_en", vs1_en);   check(4, "vs2_en", vs2_en);   check(5, "vp_en", vp_en);
            check(6, "rail_hi", rail_hi); check(7, "st", st);           check(8, "sr", sr);
            check(9, "ps_win", ps_win);   check(10, "smp", smp);        check(11, "cs", cs);
            check(12, "cc", cc);          check(13, "cnt_s", cnt_s);    check(14, "cnt_c", cnt_c);
            check(15, "cnt_r", cnt_r);    check(16, "si", si);          check(17, "hist_s", hist_s);
            check(18, "hist_c", hist_c);  check(19, "diag", diag);
            check(20, "quadrant_skip", quadrant_skip);
            check(21, "bus_rdata", bus_rdata); check(22, "bus_err", bus_err);
        end
    endtask

    initial begin
        for (k = 0; k < NOUT; k = k + 1) reported[k] = 1'b0;
        if (!$value$plusargs("vec=%s", vecfile)) $fatal(1, "usage: vvp sim +vec=FILE");
        fd = $fopen(vecfile, "r");
        if (fd == 0) $fatal(1, "cannot open the vector file");
        tick = 0;
        // reset: every input X, an edge inside it
        clk = 1'b0; rst_n = 1'b1;
        ig = 1'bx; vs2_ok = 1'bx; cmp_s = 1'bx; cmp_c = 1'bx; bus_we = 1'bx;
        bus_addr = 8'hxx; bus_wdata = 16'hxxxx;
        #5 rst_n = 1'b0;
        #5 clk = 1'b1;
        #5 clk = 1'b0;
        #5 rst_n = 1'b1;
        check_all;
        while (!$feof(fd)) begin
            rc = $fgets(line, fd);
            rc = $sscanf(line, "%h %h %h %h %h %h %h", a0, a1, a2, a3, a4, a5, a6);
            if (rc == 7) begin
                ig = a0[0];
                vs2_ok = a1[0];
                bus_we = a4[0];
                bus_addr = a5[7:0];
                bus_wdata = a4[0] ? a6 : 16'hxxxx;
                cmp_s = (smp === 1'b1 && sr === 1'b1) ? a2[0] : 1'bx;
                cmp_c = (smp === 1'b1 && sr === 1'b1) ? a3[0] : 1'bx;
                #5 clk = 1'b1;
                tick = tick + 1;
                #1 check_all;
                #4 clk = 1'b0;
            end
        end
        $display("XPROP_DONE ticks=%0d", tick);
        $finish;
    end
endmodule
