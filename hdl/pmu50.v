// PMU 50 digital core (patent US 2022/0041215 A1): Verilog-2005 twin of the Rust reference
// model. Specification: docs/spec.md; ports: docs/signals.md.
//
// One clock (rising edge), one asynchronous active-low power-on reset. All outputs are Moore
// (decoded from registers only). Block instances carry the names of the model's VCD sub-scopes
// (pmu50.<block>.<register>); the combinational internals of the model's scope
// `pmu50.internals` are in the generate scope `internals`.
//
// Sources: hdl/pmu50.v plus hdl/rtl/*.v (file list hdl/pmu50.f).
//
// Mutants for the verification-method check: compile with +define+MUT_<NAME> (hdl/mutants.txt).
`default_nettype none

module pmu50 #(
    // structural
    parameter integer SYNC_DEPTH = 2,     // 1..4
    parameter integer CNT_W      = 16,    // 2..16
    // reset values of the programmable registers (ticks)
    parameter integer ADAPTIVE   = 1,
    parameter integer PW         = 5,
    parameter integer PI         = 12,
    parameter integer PS         = 5,
    parameter integer SI_MAX     = 660,
    parameter integer SI_MIN     = 220,
    parameter integer T1         = 220,
    parameter integer T2         = 110,
    parameter integer CTH        = 4,
    parameter integer SMP_ON     = 10
) (
    input  wire             clk,
    input  wire             rst_n,
    // inputs
    input  wire             ig,
    input  wire             vs2_ok,
    input  wire             cmp_s,
    input  wire             cmp_c,
    input  wire             bus_we,
    input  wire [7:0]       bus_addr,
    input  wire [15:0]      bus_wdata,
    // outputs
    output wire             sig,
    output wire             vr_hi,
    output wire             vm_en,
    output wire             vs1_en,
    output wire             vs2_en,
    output wire             vp_en,
    output wire             rail_hi,
    output wire             st,
    output wire             sr,
    output wire             ps_win,
    output wire             smp,
    output wire             cs,
    output wire             cc,
    output wire [CNT_W-1:0] cnt_s,
    output wire [CNT_W-1:0] cnt_c,
    output wire [7:0]       cnt_r,
    output wire [15:0]      si,
    output wire             hist_s,
    output wire             hist_c,
    output wire             diag,
    output wire             quadrant_skip,
    output wire [15:0]      bus_rdata,
    output wire             bus_err
);
    // ------------------------------------------------------------------ 1. action switching 56a
    wire w_kon, w_koff;
    action_switching_56a #(.SYNC_DEPTH(SYNC_DEPTH)) action_switching (
        .clk(clk), .rst_n(rst_n), .ig(ig),
        .sig(sig), .kon(w_kon), .koff(w_koff),
        .vr_hi(vr_hi), .vm_en(vm_en), .vs1_en(vs1_en), .vp_en(vp_en), .rail_hi(rail_hi)
    );

    // ------------------------------------------------------------------ 2. register file
    wire        p_adaptive;
    wire [15:0] p_pw, p_pi, p_ps, p_si_max, p_si_min, p_t1, p_t2, p_smp_on;
    wire [15:0] p_si_max_nxt;
    wire [7:0]  p_cth;
    wire        w_skip_clr;
    wire        w_vld;
    register_file #(
        .SYNC_DEPTH(SYNC_DEPTH), .CNT_W(CNT_W),
        .ADAPTIVE(ADAPTIVE), .PW(PW), .PI(PI), .PS(PS), .SI_MAX(SI_MAX), .SI_MIN(SI_MIN),
        .T1(T1), .T2(T2), .CTH(CTH), .SMP_ON(SMP_ON)
    ) register_file (
        .clk(clk), .rst_n(rst_n),
        .bus_we(bus_we), .bus_addr(bus_addr), .bus_wdata(bus_wdata),
        .bus_rdata(bus_rdata), .bus_err_o(bus_err),
        .sig(sig), .cnt_s(cnt_s), .cnt_c(cnt_c), .cnt_r(cnt_r), .si(si),
        .cs(cs), .cc(cc), .hist_s(hist_s), .hist_c(hist_c), .diag(diag),
        .quadrant_skip(quadrant_skip), .vld(w_vld), .sr(sr),
        .adaptive_o(p_adaptive), .pw_o(p_pw), .pi_o(p_pi), .ps_o(p_ps),
        .si_max_o(p_si_max), .si_min_o(p_si_min), .t1_o(p_t1), .t2_o(p_t2),
        .cth_o(p_cth), .smp_on_o(p_smp_on), .si_max_nxt(p_si_max_nxt),
        .skip_clr(w_skip_clr)
    );

    // ------------------------------------------------------------------ 3. timing generator 56 / window of 54
    timing_generator_56 timing_generator (
        .clk(clk), .rst_n(rst_n),
        .sig(sig), .kon(w_kon), .koff(w_koff), .si(si),
        .pw(p_pw), .pi(p_pi), .ps(p_ps), .smp_on(p_smp_on),
        .st(st), .vs2_en(vs2_en), .ps_win(ps_win), .smp(smp)
    );

    // ------------------------------------------------------------------ 4. sensor power determination 57
    sensor_power_determination_57 sensor_power_determination (
        .clk(clk), .rst_n(rst_n), .vs2_en(vs2_en), .vs2_ok(vs2_ok), .sr(sr)
    );

    // ------------------------------------------------------------------ 5. comparator latches 58a/58b
    wire w_upd, w_first, w_cs_new, w_cc_new, w_chg_s, w_chg_c;
    comparator_latch_58ab comparator_latch (
        .clk(clk), .rst_n(rst_n), .cmp_s(cmp_s), .cmp_c(cmp_c), .smp(smp), .sr(sr),
        .cs(cs), .cc(cc), .vld(w_vld),
        .upd(w_upd), .first(w_first), .cs_new(w_cs_new), .cc_new(w_cc_new),
        .chg_s(w_chg_s), .chg_c(w_chg_c)
    );

    // ------------------------------------------------------------------ 6. up/down counters 58c/58d
    wire [CNT_W-1:0] w_cnt_s_nxt, w_cnt_c_nxt;
    wire             w_skip_nxt;
    updown_counter_58cd #(.CNT_W(CNT_W)) updown_counter (
        .clk(clk), .rst_n(rst_n),
        .upd(w_upd), .first(w_first), .cs(cs), .cc(cc), .cs_new(w_cs_new), .cc_new(w_cc_new),
        .skip_clr(w_skip_clr),
        .cnt_s(cnt_s), .cnt_c(cnt_c), .quadrant_skip(quadrant_skip),
        .cnt_s_nxt(w_cnt_s_nxt), .cnt_c_nxt(w_cnt_c_nxt), .skip_nxt(w_skip_nxt)
    );

    // ------------------------------------------------------------------ 7. drive interval changing 56b
    wire [2:0] w_fig17, w_fig18;
    drive_interval_changing_56b #(.SI_MAX(SI_MAX)) drive_interval (
        .clk(clk), .rst_n(rst_n),
        .koff(w_koff), .pulse(smp && !sig), .sr(sr), .chg_s(w_chg_s), .chg_c(w_chg_c),
        .adaptive(p_adaptive), .si_min(p_si_min), .si_max(p_si_max), .si_max_nxt(p_si_max_nxt),
        .t1(p_t1), .t2(p_t2),
        .cth(p_cth),
        .si(si), .hist_s(hist_s), .hist_c(hist_c), .cnt_r(cnt_r),
        .fig17(w_fig17), .fig18(w_fig18)
    );

    // ------------------------------------------------------------------ 8. count diagnosis
    count_diagnosis #(.CNT_W(CNT_W)) count_diagnosis (
        .clk(clk), .rst_n(rst_n),
        .cnt_s_nxt(w_cnt_s_nxt), .cnt_c_nxt(w_cnt_c_nxt), .skip_nxt(w_skip_nxt), .diag(diag)
    );

    // ------------------------------------------------------------------ internals (model scope pmu50.internals)
    // Combinational values of the cycle that ends at the next edge; for waveforms and lockstep
    // only (no logic is driven from here, synthesis removes it).
    generate
        if (1) begin : internals
            /* verilator lint_off UNUSEDSIGNAL */
            wire       kon      = w_kon;
            wire       koff     = w_koff;
            wire       upd      = w_upd;
            wire       first    = w_first;
            wire       chg_s    = w_chg_s;
            wire       chg_c    = w_chg_c;
            wire       skip_clr = w_skip_clr;
            wire [2:0] fig17    = w_fig17;
            wire [2:0] fig18    = w_fig18;
            /* verilator lint_on UNUSEDSIGNAL */
        end
    endgenerate
endmodule

`default_nettype wire
