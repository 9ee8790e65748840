// pmu50: digital core of power management unit 50 (US 2022/0041215 A1, FIG. 14 / FIG. 20).
//
// Third embodiment (timing signal St, programmable window Pw + Pi + Ps, comparators on Vs2,
// counters on Vp) with the second embodiment's adaptive drive interval ([0413]-[0414]).
// Behaviour: docs/spec.md; ports: docs/signals.md (the contract).
//
// Clocking (spec 1): one rising-edge clock, asynchronous active-low power-on reset. Every output
// is decoded from registers only (Moore): no input reaches an output in the same cycle.
//
// Blocks, in the spec's evaluation order:
//   u_key    pmu_keysync         56a / regulator 51: IG -> Sig, rail enables      (spec 2.1)
//   u_regs   pmu_regbank         register map, parameter set cfg_q                 (spec 2.8)
//   u_timer  pmu_wake_timer      56 / 54: St, Vs2 window, sampling strobe          (spec 2.2)
//   u_rail   pmu_rail_monitor    57: Sr                                            (spec 2.3)
//   u_latch  pmu_sign_latch      58a/58b: Cs, Cc                                   (spec 2.4)
//   u_count  pmu_quad_counter    58c/58d: CNTs, CNTc, quadrant skip                (spec 2.5)
//   u_adapt  pmu_interval_adapt  56b: drive interval Si, history, CNTr             (spec 2.6)
//   u_check  pmu_count_check     count diagnosis                                   (spec 2.7)

module pmu50 import pmu50_alt_pkg::*; #(
  // Structural parameters (spec 1)
  parameter int unsigned SYNC_DEPTH = 2,      // 1..4
  parameter int unsigned CNT_W      = 16,     // 2..16
  // Reset values of the programmable registers (spec 2.8; patent defaults at a 10 us clock)
  parameter bit          ADAPTIVE   = 1'b1,
  parameter int unsigned PW         = 5,
  parameter int unsigned PI         = 12,
  parameter int unsigned PS         = 5,
  parameter int unsigned SI_MAX     = 660,
  parameter int unsigned SI_MIN     = 220,
  parameter int unsigned T1         = 220,
  parameter int unsigned T2         = 110,
  parameter int unsigned CTH        = 4,
  parameter int unsigned SMP_ON     = 10
) (
  input  logic             clk,
  input  logic             rst_n,
  // inputs
  input  logic             ig,
  input  logic             vs2_ok,
  input  logic             cmp_s,
  input  logic             cmp_c,
  input  logic             bus_we,
  input  logic [7:0]       bus_addr,
  input  logic [15:0]      bus_wdata,
  // outputs
  output logic             sig,
  output logic             vr_hi,
  output logic             vm_en,
  output logic             vs1_en,
  output logic             vs2_en,
  output logic             vp_en,
  output logic             rail_hi,
  output logic             st,
  output logic             sr,
  output logic             ps_win,
  output logic             smp,
  output logic             cs,
  output logic             cc,
  output logic [CNT_W-1:0] cnt_s,
  output logic [CNT_W-1:0] cnt_c,
  output logic [7:0]       cnt_r,
  output logic [15:0]      si,
  output logic             hist_s,
  output logic             hist_c,
  output logic             diag,
  output logic             quadrant_skip,
  output logic [15:0]      bus_rdata,
  output logic             bus_err
);

  // Reset value of the parameter set, from the top's parameters.
  localparam cfg_t CfgReset = '{
    adaptive: ADAPTIVE,
    pw:       PW[15:0],
    pi:       PI[15:0],
    ps:       PS[15:0],
    si_max:   SI_MAX[15:0],
    si_min:   SI_MIN[15:0],
    t1:       T1[15:0],
    t2:       T2[15:0],
    cth:      CTH[7:0],
    smp_on:   SMP_ON[15:0]
  };

  // ---- nets between the blocks ----
  // key_stages, smp_take and the FIG. 17/18 paths feed no port: they are kept for observation
  // (waveforms, the verification map), as the spec's internal signals (docs/signals.md).
  /* verilator lint_off UNUSEDSIGNAL */
  logic [SYNC_DEPTH-1:0] key_stages;
  logic                  key_on, key_rise, key_fall;

  cfg_t                  cfg;
  logic [15:0]           si_max_next;
  logic                  qskip_clr;

  logic                  smp_strobe, vs2_on;
  logic                  sr_q;

  logic                  sign_s, sign_c, sign_s_new, sign_c_new;
  logic                  smp_take, smp_first, flip_s, flip_c, smp_vld;

  logic [CNT_W-1:0]      cnt_s_q, cnt_c_q, cnt_s_next, cnt_c_next;
  logic                  qskip_q, qskip_next;

  logic [15:0]           interval;
  logic                  hist_s_q, hist_c_q;
  logic [7:0]            cnt_r_q;
  fig17_e                fig17_path;
  fig18_e                fig18_path;
  logic                  adapt_pulse;
  /* verilator lint_on UNUSEDSIGNAL */

  logic                  diag_q;

  // 1. Action switching unit 56a, regulator 51 and rail enables (spec 2.1, [0196]-[0208]).
  pmu_keysync #(
    .DEPTH (SYNC_DEPTH)
  ) u_key (
    .clk,
    .rst_n,
    .ig_i       (ig),
    .stage_o    (key_stages),
    .key_on_o   (key_on),
    .key_rise_o (key_rise),
    .key_fall_o (key_fall)
  );

  // 2. Register file (spec 2.8): parameters in force = register values before the edge.
  pmu_regbank #(
    .SYNC_DEPTH (SYNC_DEPTH),
    .CNT_W      (CNT_W),
    .CFG_RESET  (CfgReset)
  ) u_regs (
    .clk,
    .rst_n,
    .bus_we_i      (bus_we),
    .bus_addr_i    (bus_addr),
    .bus_wdata_i   (bus_wdata),
    .rdata_o       (bus_rdata),
    .bus_err_o     (bus_err),
    .key_on_i      (key_on),
    .cnt_s_i       (cnt_s_q),
    .cnt_c_i       (cnt_c_q),
    .cnt_r_i       (cnt_r_q),
    .interval_i    (interval),
    .sign_s_i      (sign_s),
    .sign_c_i      (sign_c),
    .hist_s_i      (hist_s_q),
    .hist_c_i      (hist_c_q),
    .diag_i        (diag_q),
    .qskip_i       (qskip_q),
    .vld_i         (smp_vld),
    .sr_i          (sr_q),
    .cfg_o         (cfg),
    .si_max_next_o (si_max_next),
    .qskip_clr_o   (qskip_clr)
  );

  // 3. Timing generator of 56 and window of 54 (spec 2.2).
  pmu_wake_timer u_timer (
    .clk,
    .rst_n,
    .key_on_i   (key_on),
    .key_rise_i (key_rise),
    .key_fall_i (key_fall),
    .interval_i (interval),
    .cfg_i      (cfg),
    .st_o       (st),
    .vs2_en_o   (vs2_on),
    .ps_win_o   (ps_win),
    .smp_o      (smp_strobe)
  );

  // 4. Sensor power determination unit 57 (spec 2.3).
  pmu_rail_monitor u_rail (
    .clk,
    .rst_n,
    .vs2_en_i (vs2_on),
    .vs2_ok_i (vs2_ok),
    .sr_o     (sr_q)
  );

  // 5. Comparator latches 58a/58b (spec 2.4).
  pmu_sign_latch u_latch (
    .clk,
    .rst_n,
    .cmp_s_i      (cmp_s),
    .cmp_c_i      (cmp_c),
    .smp_i        (smp_strobe),
    .sr_i         (sr_q),
    .sign_s_o     (sign_s),
    .sign_c_o     (sign_c),
    .sign_s_new_o (sign_s_new),
    .sign_c_new_o (sign_c_new),
    .take_o       (smp_take),
    .first_o      (smp_first),
    .flip_s_o     (flip_s),
    .flip_c_o     (flip_c),
    .vld_o        (smp_vld)
  );

  // 6. Up/down counters 58c/58d (spec 2.5).
  pmu_quad_counter #(
    .CNT_W (CNT_W)
  ) u_count (
    .clk,
    .rst_n,
    .first_i      (smp_first),
    .sign_s_i     (sign_s),
    .sign_c_i     (sign_c),
    .sign_s_new_i (sign_s_new),
    .sign_c_new_i (sign_c_new),
    .flip_s_i     (flip_s),
    .flip_c_i     (flip_c),
    .qskip_clr_i  (qskip_clr),
    .cnt_s_o      (cnt_s_q),
    .cnt_c_o      (cnt_c_q),
    .cnt_s_next_o (cnt_s_next),
    .cnt_c_next_o (cnt_c_next),
    .qskip_o      (qskip_q),
    .qskip_next_o (qskip_next)
  );

  // 7. Drive interval changing unit 56b (spec 2.6): runs at key-off sampling strobes only.
  assign adapt_pulse = smp_strobe & ~key_on;

  pmu_interval_adapt #(
    .SI_RESET (SI_MAX[15:0])
  ) u_adapt (
    .clk,
    .rst_n,
    .key_fall_i    (key_fall),
    .pulse_i       (adapt_pulse),
    .sr_i          (sr_q),
    .flip_s_i      (flip_s),
    .flip_c_i      (flip_c),
    .cfg_i         (cfg),
    .si_max_next_i (si_max_next),
    .interval_o    (interval),
    .hist_s_o      (hist_s_q),
    .hist_c_o      (hist_c_q),
    .cnt_r_o       (cnt_r_q),
    .fig17_o       (fig17_path),
    .fig18_o       (fig18_path)
  );

  // 8. Count diagnosis (spec 2.7).
  pmu_count_check #(
    .CNT_W (CNT_W)
  ) u_check (
    .clk,
    .rst_n,
    .cnt_s_next_i (cnt_s_next),
    .cnt_c_next_i (cnt_c_next),
    .qskip_next_i (qskip_next),
    .diag_o       (diag_q)
  );

  // ---- outputs (all registered) ----
  assign sig           = key_on;
  assign vr_hi         = key_on;   // VR 6 V with the key on, 4 V off ([0340])
  assign vm_en         = key_on;   // unit 52 ([0202], [0205])
  assign vs1_en        = key_on;   // unit 53 ([0203], [0205])
  assign rail_hi       = key_on;   // Vs2/Vp at Vcc1 on, Vcc2 off ([0343], [0345], [0348])
  assign vp_en         = 1'b1;     // unit 55: Vp always ([0330])
  assign vs2_en        = vs2_on;
  assign smp           = smp_strobe;
  assign sr            = sr_q;
  assign cs            = sign_s;
  assign cc            = sign_c;
  assign cnt_s         = cnt_s_q;
  assign cnt_c         = cnt_c_q;
  assign quadrant_skip = qskip_q;
  assign cnt_r         = cnt_r_q;
  assign si            = interval;
  assign hist_s        = hist_s_q;
  assign hist_c        = hist_c_q;
  assign diag          = diag_q;

endmodule : pmu50
