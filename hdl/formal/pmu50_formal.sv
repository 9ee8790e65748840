// Formal property kit of the PMU 50 core (docs/spec.md), over the contract ports of `pmu50`
// (docs/signals.md) and its parameters only: it binds to any RTL with that interface.
//
// Formal top `pmu50_formal` instantiates the DUT `pmu50` and holds every property as an
// immediate assertion in an `always @(posedge clk)` block (open-source yosys reads them with
// `read_verilog -formal -sv`). State the rules need (the synchronized key, the parameter
// registers, the timer, "a sample has been taken") is reconstructed here from the ports: a
// shadow that sees only what the DUT's ports show, never the DUT's internals.
//
// Reset: rst_n is low in the first cycle only (cycle 0); registered outputs hold their reset
// values at cycle 1; rules over one edge (`$past`) are checked from cycle 2 on.
//
// Every property is one line `// @prop NAME | SPEC | MEANING` followed by its labelled
// assertion `NAME: assert (...)` and the reachability cover of its antecedent
// `reach_X: cover (...)` for `prop_X`. hdl/formal/run.py checks each label on its own; the Rust
// twins (rtl_model/core/tests/formal_twins.rs) carry the same names, and a test there compares
// the two lists.
//
// Vacuity: an `assume` in the RTL under test constrains every check. A proof whose antecedent
// cover cannot be reached under those assumptions says nothing, and run.py reports it
// `vacuous`; the covers reach_reset_state and reach_keyoff_period show that the assumptions
// leave the reset state and one whole key-off period (key off, then the next period's st).
`default_nettype none

module pmu50_formal #(
    parameter integer SYNC_DEPTH = 2,
    parameter integer CNT_W      = 16,
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
    input wire        clk,
    input wire        ig,
    input wire        vs2_ok,
    input wire        cmp_s,
    input wire        cmp_c,
    input wire        bus_we,
    input wire [7:0]  bus_addr,
    input wire [15:0] bus_wdata
);
    // ------------------------------------------------------------------ reset sequence
    reg f_started = 1'b0;   // 0 in cycle 0 only: rst_n low there
    reg f_live    = 1'b0;   // 1 from cycle 2: $past values are of cycles out of reset
    always @(posedge clk) begin
        f_started <= 1'b1;
        f_live    <= f_started;
    end
    wire rst_n = f_started;

    // ------------------------------------------------------------------ DUT
    wire             sig, vr_hi, vm_en, vs1_en, vs2_en, vp_en, rail_hi, st, sr, ps_win, smp;
    wire             cs, cc, hist_s, hist_c, diag, quadrant_skip, bus_err;
    wire [CNT_W-1:0] cnt_s, cnt_c;
    wire [7:0]       cnt_r;
    wire [15:0]      si, bus_rdata;

    pmu50 #(
        .SYNC_DEPTH(SYNC_DEPTH), .CNT_W(CNT_W), .ADAPTIVE(ADAPTIVE), .PW(PW), .PI(PI), .PS(PS),
        .SI_MAX(SI_MAX), .SI_MIN(SI_MIN), .T1(T1), .T2(T2), .CTH(CTH), .SMP_ON(SMP_ON)
    ) dut (.*);  // every port to the net of its name: the inputs, rst_n and the wires above

    // ------------------------------------------------------------------ shadows from the ports
    // The key through SYNC_DEPTH flops (spec 2.1).
    reg [SYNC_DEPTH-1:0] f_pipe;
    always @(posedge clk)
        if (!rst_n) f_pipe <= {SYNC_DEPTH{1'b0}};
        else        f_pipe <= {f_pipe, ig};

    // Register file (spec 2.8, legality spec 4): what the bus wrote while sig = 1.
    reg        f_adaptive;
    reg [15:0] f_pw, f_pi, f_ps, f_si_max, f_si_min, f_t1, f_t2, f_smp_on;
    reg [7:0]  f_cth;
    wire f_status_w = bus_we && sig && (bus_addr == 8'h14);
    wire f_is_param = (bus_addr >= 8'h02) && (bus_addr <= 8'h0B);
    wire        c_adaptive = (bus_addr == 8'h02) ? bus_wdata[0]   : f_adaptive;
    wire [15:0] c_pw       = (bus_addr == 8'h03) ? bus_wdata      : f_pw;
    wire [15:0] c_pi       = (bus_addr == 8'h04) ? bus_wdata      : f_pi;
    wire [15:0] c_ps       = (bus_addr == 8'h05) ? bus_wdata      : f_ps;
    wire [15:0] c_si_max   = (bus_addr == 8'h06) ? bus_wdata      : f_si_max;
    wire [15:0] c_si_min   = (bus_addr == 8'h07) ? bus_wdata      : f_si_min;
    wire [15:0] c_t1       = (bus_addr == 8'h08) ? bus_wdata      : f_t1;
    wire [15:0] c_t2       = (bus_addr == 8'h09) ? bus_wdata      : f_t2;
    wire [7:0]  c_cth      = (bus_addr == 8'h0A) ? bus_wdata[7:0] : f_cth;
    wire [15:0] c_smp_on   = (bus_addr == 8'h0B) ? bus_wdata      : f_smp_on;
    wire [17:0] c_wt       = {2'b00, c_pw} + {2'b00, c_pi} + {2'b00, c_ps};
    wire [15:0] c_shortest = c_adaptive ? c_si_min : c_si_max;
    wire f_legal = (c_ps != 0) && (c_si_max != 0) && (c_si_min != 0) && (c_t1 != 0) &&
                   (c_t2 != 0) && (c_smp_on != 0) && (c_cth != 0) && (c_si_min <= c_si_max) &&
                   ((c_pw != 0) || (c_pi != 0)) && (c_wt < {2'b00, c_shortest});
    wire f_param_wr = bus_we && sig && f_is_param && f_legal;
    wire f_refused  = bus_we && !f_status_w && !f_param_wr;
    wire f_skip_clr = f_status_w && bus_wdata[5];
    wire f_err_clr  = f_status_w && bus_wdata[9];
    always @(posedge clk)
        if (!rst_n) begin
            f_adaptive <= (ADAPTIVE != 0);
            f_pw <= PW; f_pi <= PI; f_ps <= PS; f_si_max <= SI_MAX; f_si_min <= SI_MIN;
            f_t1 <= T1; f_t2 <= T2; f_cth <= CTH; f_smp_on <= SMP_ON;
        end else if (f_param_wr) begin
            f_adaptive <= c_adaptive;
            f_pw <= c_pw; f_pi <= c_pi; f_ps <= c_ps; f_si_max <= c_si_max; f_si_min <= c_si_min;
            f_t1 <= c_t1; f_t2 <= c_t2; f_cth <= c_cth; f_smp_on <= c_smp_on;
        end

    // Timer (spec 2.2): restarts when sig changes (the key pipeline's next sig) and at the end
    // of each period.
    wire f_sig_nxt;
    generate
        if (SYNC_DEPTH == 1) begin : g_nxt1
            assign f_sig_nxt = ig;
        end else begin : g_nxtn
            assign f_sig_nxt = f_pipe[SYNC_DEPTH-2];
        end
    endgenerate
    reg  [15:0] f_tmr;
    wire [16:0] f_tinc   = {1'b0, f_tmr} + 17'd1;
    wire [15:0] f_period = sig ? f_smp_on : si;
    wire [17:0] f_ps_start = {2'b00, f_pw} + {2'b00, f_pi};
    wire [17:0] f_wt       = f_ps_start + {2'b00, f_ps};
    always @(posedge clk)
        if (!rst_n) f_tmr <= 16'd0;
        else        f_tmr <= (f_sig_nxt != sig || f_tinc >= {1'b0, f_period}) ? 16'd0 : f_tinc[15:0];

    // "A sample has been taken since reset" (spec 2.4).
    reg f_vld;
    always @(posedge clk)
        if (!rst_n) f_vld <= 1'b0;
        else        f_vld <= f_vld || (smp && sr);

    // This cycle's edge, from the ports (spec 2.4-2.6).
    wire f_upd   = smp && sr;
    wire f_first = f_upd && !f_vld;
    wire f_chg_s = f_upd && f_vld && (cmp_s != cs);
    wire f_chg_c = f_upd && f_vld && (cmp_c != cc);
    wire f_pulse = smp && !sig;
    wire f_adp   = f_pulse && f_adaptive && sr;                  // FIG. 17/18 run
    wire f_det   = f_chg_s ? !hist_s : (f_chg_c && !hist_c);     // FIG. 18 detection
    wire [16:0] f_sub   = {1'b0, si} - {1'b0, f_t1};
    wire [15:0] f_dec   = f_sub[16] ? 16'd0 : f_sub[15:0];
    wire [15:0] f_short = (f_dec < f_si_min) ? f_si_min : f_dec;  // S6 with the clamp
    wire [16:0] f_add   = {1'b0, si} + {1'b0, f_t2};
    wire [15:0] f_long  = (f_add > {1'b0, f_si_max}) ? f_si_max : f_add[15:0];  // S10
    wire [7:0]  f_inc   = (cnt_r == 8'hFF) ? 8'hFF : cnt_r + 8'd1;  // S9
    wire f_expand = f_adp && !f_det && (si < f_si_max) && (cnt_r >= f_cth);
    wire f_count  = f_adp && !f_det && (si < f_si_max) && (cnt_r <  f_cth);
    // Values of the cycle before (the $past the wires below need).
    reg f_sig_p;
    reg [CNT_W-1:0] f_cnt_s_p, f_cnt_c_p;
    always @(posedge clk) begin
        f_sig_p   <= sig;
        f_cnt_s_p <= cnt_s;
        f_cnt_c_p <= cnt_c;
    end
    wire f_koff   = f_live && f_sig_p && !sig;                    // sig fell at the last edge

    // Counter arithmetic at CNT_W bits.
    localparam [CNT_W-1:0] ONE  = 1;
    localparam [CNT_W-1:0] TWO  = 2;
    localparam [CNT_W-1:0] ONES = {CNT_W{1'b1}};
    wire [CNT_W-1:0] f_d = cnt_s - cnt_c;
    wire [CNT_W-1:0] f_ds = cnt_s - f_cnt_s_p;
    wire [CNT_W-1:0] f_dc = cnt_c - f_cnt_c_p;
    wire [15:0] f_sext_s = $signed(cnt_s);
    wire [15:0] f_sext_c = $signed(cnt_c);

    // The last accepted parameter write, for its read-back (independent of the shadow).
    reg        f_wr_v;
    reg [7:0]  f_wr_addr;
    reg [15:0] f_wr_data;
    always @(posedge clk) begin
        f_wr_v    <= rst_n && f_param_wr;
        f_wr_addr <= bus_addr;
        f_wr_data <= (bus_addr == 8'h02) ? {15'd0, bus_wdata[0]} :
                     (bus_addr == 8'h0A) ? {8'd0, bus_wdata[7:0]} : bus_wdata;
    end

    // Read mux expected from the shadows and the ports (spec 2.8).
    reg [15:0] f_rd;
    always @* begin
        case (bus_addr)
            8'h00: f_rd = 16'h5050;
            8'h01: f_rd = 16'h0001;
            8'h02: f_rd = {15'd0, f_adaptive};
            8'h03: f_rd = f_pw;
            8'h04: f_rd = f_pi;
            8'h05: f_rd = f_ps;
            8'h06: f_rd = f_si_max;
            8'h07: f_rd = f_si_min;
            8'h08: f_rd = f_t1;
            8'h09: f_rd = f_t2;
            8'h0A: f_rd = {8'd0, f_cth};
            8'h0B: f_rd = f_smp_on;
            8'h0C: f_rd = {3'b000, CNT_W[4:0], 5'b00000, SYNC_DEPTH[2:0]};
            8'h10: f_rd = f_sext_s;
            8'h11: f_rd = f_sext_c;
            8'h12: f_rd = {8'd0, cnt_r};
            8'h13: f_rd = si;
            8'h14: f_rd = {6'd0, bus_err, sr, f_vld, sig, quadrant_skip, diag, hist_c, hist_s, cc, cs};
            default: f_rd = 16'd0;
        endcase
    end
    wire f_rd_fixed  = (bus_addr <= 8'h01) || (bus_addr == 8'h0C) ||
                       ((bus_addr > 8'h0C) && (bus_addr < 8'h10)) || (bus_addr > 8'h14);
    wire f_rd_cnt    = (bus_addr >= 8'h10) && (bus_addr <= 8'h13);

    // One whole key-off period: the key fell and has stayed off since (spec 2.2, 3 [0226]).
    reg f_koff_seen;
    always @(posedge clk)
        if (!rst_n || sig) f_koff_seen <= 1'b0;
        else if (f_koff)   f_koff_seen <= 1'b1;

    // ------------------------------------------------------------------ kit-level covers
    always @(posedge clk) begin
        // the reset state: cycle 1, the registered outputs at their reset values
        if (f_started && !f_live) reach_reset_state: cover (1'b1);
        // one full key-off period: after the key fell, the st of the next period
        if (f_live) reach_keyoff_period: cover (f_koff_seen && st && !sig);
    end

    // ------------------------------------------------------------------ properties
    always @(posedge clk) begin
        if (f_started && !f_live) begin
            // @prop prop_reset_values | 1, 2.1-2.8 reset columns | after reset every registered output holds its reset value
            prop_reset_values: assert (!sig && !sr && !cs && !cc && cnt_s == 0 && cnt_c == 0 &&
                cnt_r == 0 && si == SI_MAX[15:0] && !hist_s && !hist_c && !diag &&
                !quadrant_skip && bus_rdata == 0 && !bus_err);
            reach_reset_values: cover (1'b1);
            // @prop prop_reset_window | 2.2, 3 [0226] | the first tick after reset starts an intermittent output (st, vs2_en) with no sample
            prop_reset_window: assert (st && vs2_en && !smp);
            reach_reset_window: cover (1'b1);
        end
        if (f_started) begin
            // @prop prop_sig_sync | 2.1 I1 [0213] | sig is ig delayed by exactly SYNC_DEPTH flops
            prop_sig_sync: assert (sig == f_pipe[SYNC_DEPTH-1]);
            reach_sig_sync: cover (sig);
            // @prop prop_rails_follow_sig | 2.1 [0340]-[0348] | vr_hi, vm_en, vs1_en, rail_hi equal sig; vp_en is always 1
            prop_rails_follow_sig: assert (vr_hi == sig && vm_en == sig && vs1_en == sig &&
                rail_hi == sig && vp_en);
            reach_rails_follow_sig: cover (sig);
            // @prop prop_st_pulse | 2.2 [0336] | st is high exactly at timer 0 with the key off
            prop_st_pulse: assert (st == (!sig && f_tmr == 16'd0));
            reach_st_pulse: cover (!sig && f_tmr != 16'd0);
            // @prop prop_vs2_en_window | 2.2 [0347] | vs2_en is high with the key on, and with the key off for Wt = Pw + Pi + Ps ticks from st
            prop_vs2_en_window: assert (vs2_en == (sig || {2'b00, f_tmr} < f_wt));
            reach_vs2_en_window: cover (!sig && {2'b00, f_tmr} >= f_wt);
            // @prop prop_ps_window | 2.2 [0322] | ps_win is high in the last Ps ticks of the window, key off only
            prop_ps_window: assert (ps_win == (!sig && {2'b00, f_tmr} >= f_ps_start && {2'b00, f_tmr} < f_wt));
            reach_ps_window: cover (ps_win);
            // @prop prop_smp_key_off | 2.2 I3 [0322]-[0323] | with the key off the sampling strobe is the last tick of Ps, once per interval
            prop_smp_key_off: assert (sig || smp == ({1'b0, f_tinc} == f_wt));
            reach_smp_key_off: cover (!sig && smp);
            // @prop prop_smp_key_on | 2.2 I4 [0349] | with the key on the strobe comes every SMP_ON ticks, in phase with the key-on edge
            prop_smp_key_on: assert (!sig || smp == (f_tinc == {1'b0, f_smp_on}));
            reach_smp_key_on: cover (sig && smp);
            // @prop prop_diag | 2.7 I14 [0119] | diag is |cnt_s - cnt_c| >= 2 (CNT_W bits, signed) or quadrant_skip
            prop_diag: assert (diag == (!(f_d == 0 || f_d == ONE || f_d == ONES) || quadrant_skip));
            reach_diag: cover (diag);
        end
        if (f_live) begin
            // @prop prop_key_off_starts_output | 3 [0226] I12 | the first tick with the key off has st: an output starts at once
            prop_key_off_starts_output: assert (!f_koff || st);
            reach_key_off_starts_output: cover (f_koff);
            // @prop prop_sr_power_good | 2.3 I2 [0209] | sr is vs2_en and the Vs2 power-good of the tick before
            prop_sr_power_good: assert (sr == $past(vs2_en && vs2_ok));
            reach_sr_power_good: cover ($past(vs2_en && vs2_ok));
            // @prop prop_latch_hold | 2.4 [0211] | cs and cc hold unless the strobe came with sr
            prop_latch_hold: assert ($past(f_upd) || (cs == $past(cs) && cc == $past(cc)));
            reach_latch_hold: cover (!$past(f_upd) && f_vld);
            // @prop prop_latch_sample | 2.4 [0086]-[0087] | at a strobe with sr, cs and cc take the comparator decisions
            prop_latch_sample: assert (!$past(f_upd) || (cs == $past(cmp_s) && cc == $past(cmp_c)));
            reach_latch_sample: cover ($past(f_upd));
            // @prop prop_first_preset | 2.5 I6 [0092]-[0093] | the first sample presets (cnt_s, cnt_c) from the quadrant: Q0 (0,0) Q1 (0,1) Q2 (1,1) Q3 (1,2)
            prop_first_preset: assert (!$past(f_first) ||
                ({cs, cc} == 2'b11 && cnt_s == 0   && cnt_c == 0) ||
                ({cs, cc} == 2'b10 && cnt_s == 0   && cnt_c == ONE) ||
                ({cs, cc} == 2'b00 && cnt_s == ONE && cnt_c == ONE) ||
                ({cs, cc} == 2'b01 && cnt_s == ONE && cnt_c == TWO));
            reach_first_preset: cover ($past(f_first));
            // @prop prop_cnt_s_0096 | 2.5 [0096] | with Cc = 1 a lone Cs change counts cnt_s up (0->1) or down (1->0)
            prop_cnt_s_0096: assert (!$past(f_chg_s && !f_chg_c && cc) ||
                (cnt_s == (cs ? $past(cnt_s) + ONE : $past(cnt_s) - ONE) && cnt_c == $past(cnt_c)));
            reach_cnt_s_0096: cover ($past(f_chg_s && !f_chg_c && cc));
            // @prop prop_cnt_s_0097 | 2.5 [0097] | with Cc = 0 a lone Cs change counts cnt_s up (1->0) or down (0->1)
            prop_cnt_s_0097: assert (!$past(f_chg_s && !f_chg_c && !cc) ||
                (cnt_s == (cs ? $past(cnt_s) - ONE : $past(cnt_s) + ONE) && cnt_c == $past(cnt_c)));
            reach_cnt_s_0097: cover ($past(f_chg_s && !f_chg_c && !cc));
            // @prop prop_cnt_c_0098 | 2.5 [0098] | with Cs = 0 a lone Cc change counts cnt_c up (0->1) or down (1->0)
            prop_cnt_c_0098: assert (!$past(f_chg_c && !f_chg_s && !cs) ||
                (cnt_c == (cc ? $past(cnt_c) + ONE : $past(cnt_c) - ONE) && cnt_s == $past(cnt_s)));
            reach_cnt_c_0098: cover ($past(f_chg_c && !f_chg_s && !cs));
            // @prop prop_cnt_c_0099 | 2.5 [0099] | with Cs = 1 a lone Cc change counts cnt_c up (1->0) or down (0->1)
            prop_cnt_c_0099: assert (!$past(f_chg_c && !f_chg_s && cs) ||
                (cnt_c == (cc ? $past(cnt_c) - ONE : $past(cnt_c) + ONE) && cnt_s == $past(cnt_s)));
            reach_cnt_c_0099: cover ($past(f_chg_c && !f_chg_s && cs));
            // @prop prop_cnt_wrap | 1, 2.5 | a counter moves by exactly one step modulo 2^CNT_W (wraps, never saturates)
            prop_cnt_wrap: assert (!$past(f_chg_s ^ f_chg_c) || $past(f_first) ||
                ((f_ds == ONE || f_ds == ONES) != (f_dc == ONE || f_dc == ONES)));
            reach_cnt_wrap: cover ($past(f_chg_s ^ f_chg_c) && !$past(f_first));
            // @prop prop_cnt_hold | 2.5 I5 | without a first sample or a lone sign change both counters hold
            prop_cnt_hold: assert ($past(f_first) || $past(f_chg_s ^ f_chg_c) ||
                (cnt_s == $past(cnt_s) && cnt_c == $past(cnt_c)));
            reach_cnt_hold: cover (!$past(f_first) && !$past(f_chg_s ^ f_chg_c) && f_vld);
            // @prop prop_quadrant_skip | 2.5 I5, 2.8 | quadrant_skip is set when both signs change in one sample and held until a STATUS W1C of bit 5
            prop_quadrant_skip: assert (quadrant_skip ==
                $past((f_chg_s && f_chg_c) || (quadrant_skip && !f_skip_clr)));
            reach_quadrant_skip: cover ($past(f_chg_s && f_chg_c));
            // @prop prop_si_moves_at_pulse | 2.6 [0199] | si changes only at a key-off sample or at key-off
            prop_si_moves_at_pulse: assert (si == $past(si) || f_koff || $past(f_pulse));
            reach_si_moves_at_pulse: cover ($past(f_pulse) && si != $past(si));
            // @prop prop_key_on_holds | 3 [0168] | while the key stays on, si, hist_s, hist_c and cnt_r hold
            prop_key_on_holds: assert (!(sig && $past(sig)) ||
                (si == $past(si) && hist_s == $past(hist_s) && hist_c == $past(hist_c) && cnt_r == $past(cnt_r)));
            reach_key_on_holds: cover (sig && $past(sig));
            // @prop prop_koff_reload | 3 [0226] [0248] I12 | at key-off si is reloaded with x (a same-cycle SI_MAX write counts); history and cnt_r cleared
            prop_koff_reload: assert (!f_koff || (si == f_si_max && !hist_s && !hist_c && cnt_r == 0));
            reach_koff_reload: cover (f_koff);
            // @prop prop_fixed_interval | 2.6 I13 [0083] | with CTRL.adaptive = 0 a key-off sample sets si to x and keeps history and cnt_r
            prop_fixed_interval: assert (!$past(f_pulse && !f_adaptive) ||
                (si == $past(f_si_max) && hist_s == $past(hist_s) && hist_c == $past(hist_c) && cnt_r == $past(cnt_r)));
            reach_fixed_interval: cover ($past(f_pulse && !f_adaptive));
            // @prop prop_s1_no_rise | 2.6 S1 I2 [0264] | a key-off sample without sr changes nothing of 56b
            prop_s1_no_rise: assert (!$past(f_pulse && f_adaptive && !sr) ||
                (si == $past(si) && hist_s == $past(hist_s) && hist_c == $past(hist_c) && cnt_r == $past(cnt_r)));
            reach_s1_no_rise: cover ($past(f_pulse && f_adaptive && !sr));
            // @prop prop_si_shorten | 2.6 S4-S6 I10 I11 [0260]-[0262] | a detected rotation clears cnt_r and shortens si by T1, clamped to the minimum
            prop_si_shorten: assert (!$past(f_adp && f_det) ||
                (cnt_r == 0 && si == $past(si <= f_si_min ? si : f_short)));
            reach_si_shorten: cover ($past(f_adp && f_det));
            // @prop prop_si_hold_at_max | 2.6 S7 I9 [0285] | no detection with si at x: si and cnt_r hold
            prop_si_hold_at_max: assert (!$past(f_adp && !f_det && si >= f_si_max) ||
                (si == $past(si) && cnt_r == $past(cnt_r)));
            reach_si_hold_at_max: cover ($past(f_adp && !f_det && si >= f_si_max));
            // @prop prop_si_expand | 2.6 S8-S10 I8 I10 [0250] | cnt_r at Cth (checked before counting) expands si by T2, clamped to x, and counts
            prop_si_expand: assert (!$past(f_expand) || (si == $past(f_long) && cnt_r == $past(f_inc)));
            reach_si_expand: cover ($past(f_expand));
            // @prop prop_s11_clear | 2.6 S11 I7 [0291] | an expansion clears both change histories
            prop_s11_clear: assert (!$past(f_expand) || (!hist_s && !hist_c));
            reach_s11_clear: cover ($past(f_expand));
            // @prop prop_cnt_r_count | 2.6 S8:N S9 [0248] | a quiet pulse below Cth counts cnt_r up by one and keeps si and the history
            prop_cnt_r_count: assert (!$past(f_count) || (cnt_r == $past(cnt_r) + 8'd1 &&
                si == $past(si) && hist_s == $past(hist_s) && hist_c == $past(hist_c)));
            reach_cnt_r_count: cover ($past(f_count));
            // @prop prop_cnt_r_saturates | 1, 2.6 S9 | cnt_r holds, clears or counts up by one, and never wraps past 255
            prop_cnt_r_saturates: assert (cnt_r == $past(cnt_r) || cnt_r == 0 ||
                ($past(cnt_r) != 8'hFF && cnt_r == $past(cnt_r) + 8'd1));
            reach_cnt_r_saturates: cover (cnt_r != 8'd0 && cnt_r != $past(cnt_r));
            // @prop prop_hist_detect | 2.6 FIG. 18 S22-S23 S27-S28 [0268]-[0279] | a detection sets the history of the changed sign and clears the other (Cs first)
            prop_hist_detect: assert (!$past(f_adp && f_det) ||
                ({hist_s, hist_c} == ($past(f_chg_s) ? 2'b10 : 2'b01)));
            reach_hist_detect: cover ($past(f_adp && f_det));
            // @prop prop_hist_moves | 2.6 FIG. 18 | hist_s and hist_c change only at an adaptive key-off sample with sr, or at key-off
            prop_hist_moves: assert ((hist_s == $past(hist_s) && hist_c == $past(hist_c)) || f_koff || $past(f_adp));
            reach_hist_moves: cover ($past(f_adp) && (hist_s != $past(hist_s) || hist_c != $past(hist_c)));
            // @prop prop_read_fixed | 2.8 | ID, VERSION and CFG read their constants, unmapped addresses 0, one cycle after the address
            prop_read_fixed: assert (!$past(f_rd_fixed) || bus_rdata == $past(f_rd));
            reach_read_fixed: cover ($past(f_rd_fixed));
            // @prop prop_read_params | 2.8 [0259] [0321] | a parameter register reads what the last accepted write (or reset) put there
            prop_read_params: assert (!$past(f_is_param) || bus_rdata == $past(f_rd));
            reach_read_params: cover ($past(f_is_param));
            // @prop prop_read_counters | 2.8 | CNT_S and CNT_C read sign-extended from CNT_W, CNT_R and SI as they were
            prop_read_counters: assert (!$past(f_rd_cnt) || bus_rdata == $past(f_rd));
            reach_read_counters: cover ($past(f_rd_cnt));
            // @prop prop_read_status | 2.8 | STATUS reads cs cc hist_s hist_c diag quadrant_skip sig vld sr bus_err
            prop_read_status: assert (!$past(bus_addr == 8'h14) || bus_rdata == $past(f_rd));
            reach_read_status: cover ($past(bus_addr == 8'h14));
            // @prop prop_write_key_off_refused | 2.8 I15 [0205] | a write while sig = 0 is refused: bus_err is set
            prop_write_key_off_refused: assert (!$past(bus_we && !sig) || bus_err);
            reach_write_key_off_refused: cover ($past(bus_we && !sig));
            // @prop prop_write_illegal_refused | 2.8, 4 [0319] [0321] | a parameter write making the set illegal is refused: bus_err is set
            prop_write_illegal_refused: assert (!$past(bus_we && sig && f_is_param && !f_legal) || bus_err);
            reach_write_illegal_refused: cover ($past(bus_we && sig && f_is_param && !f_legal));
            // @prop prop_write_ro_refused | 2.8 | a write to a read-only or unmapped address is refused: bus_err is set
            prop_write_ro_refused: assert (!$past(bus_we && sig && !f_is_param && bus_addr != 8'h14) || bus_err);
            reach_write_ro_refused: cover ($past(bus_we && sig && !f_is_param && bus_addr != 8'h14));
            // @prop prop_write_accepted | 2.8, 4 | a legal parameter write with sig = 1 is taken (read back next cycle) and leaves bus_err as it was
            prop_write_accepted: assert ((!$past(f_param_wr) || bus_err == $past(bus_err)) &&
                (!$past(f_wr_v && bus_addr == f_wr_addr) || bus_rdata == $past(f_wr_data)));
            reach_write_accepted: cover ($past(f_wr_v && bus_addr == f_wr_addr));
            // @prop prop_bus_err_w1c | 2.8 [0259] | bus_err is sticky: set by a refused write, cleared only by a STATUS W1C of bit 9 (set wins)
            prop_bus_err_w1c: assert (bus_err == $past(f_refused || (bus_err && !f_err_clr)));
            reach_bus_err_w1c: cover ($past(f_refused));
        end
    end
endmodule

`default_nettype wire
