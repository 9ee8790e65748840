// pmu_interval_adapt: drive interval changing unit 56b.
//
// Second embodiment, adopted by the third ([0413]-[0414]): the drive interval Si of the second
// sensor is shortened by T1 when a rotation is detected and expanded by T2 once Cth quiet pulses
// have passed ([0214]-[0262]), within [minimum, x] ([0260]-[0262], I10). Rotation detection with
// the change-history flip-flops follows FIG. 18 S20-S28 ([0268]-[0279]); the interval update
// follows FIG. 17 S1-S11 ([0263]-[0291]); S11 continues to S9 (I7, [0250], [0291]); the Cth test
// comes before the S9 increment (I8); S7: Y does not count (I9, [0285]). Spec 2.6.
//
// Key-off (spec 3, I12, [0226], [0248]): Si := x as x stands after the edge, history and CNTr
// cleared. With adaptive = 0 (first embodiment, fixed cycle T [0083], I13) each pulse reloads x.

module pmu_interval_adapt import pmu50_alt_pkg::*; #(
  parameter logic [15:0] SI_RESET = 16'd660   // x at power-on
) (
  input  logic        clk,
  input  logic        rst_n,
  input  logic        key_fall_i,      // koff
  input  logic        pulse_i,         // key-off sampling strobe: smp & !sig
  input  logic        sr_i,            // Vs2 rose (S1)
  input  logic        flip_s_i,        // Cs changed at this sample
  input  logic        flip_c_i,        // Cc changed at this sample
  /* verilator lint_off UNUSEDSIGNAL */
  input  cfg_t        cfg_i,           // parameters in force (the window fields are not used here)
  /* verilator lint_on UNUSEDSIGNAL */
  input  logic [15:0] si_max_next_i,   // x after this edge (a same-cycle write counts)
  output logic [15:0] interval_o,
  output logic        hist_s_o,
  output logic        hist_c_o,
  output logic [7:0]  cnt_r_o,
  output fig17_e      fig17_o,         // FIG. 17 path of this edge (comb)
  output fig18_e      fig18_o          // FIG. 18 path of this edge (comb)
);

  logic [15:0] interval_q, interval_d;
  logic        hist_s_q, hist_s_d;
  logic        hist_c_q, hist_c_d;
  logic [7:0]  cnt_r_q, cnt_r_d;

  // FIG. 18 result
  logic        rot_detected;
  logic        det_hist_s, det_hist_c;
  fig18_e      det_path;

  // Candidate intervals of S6 / S10 and the next CNTr of S9
  logic [15:0] shorter_si;
  logic [16:0] longer_sum;
  logic [15:0] longer_si;
  logic [7:0]  cnt_r_inc;

  // ---- FIG. 18: rotation detection with change history ([0237]-[0243], [0268]-[0279]) ----
  // S20 tests Cs first, so a sample where both signs changed takes the Cs branch (I5).
  always_comb begin
    rot_detected = 1'b0;
    det_hist_s   = hist_s_q;
    det_hist_c   = hist_c_q;
    det_path     = F18_S25_NO_CHANGE;
    if (flip_s_i) begin
      if (hist_s_q) begin
        det_path     = F18_S21_CS_REPEAT;          // S21: Y -> S24
      end else begin
        rot_detected = 1'b1;                       // S22, S23
        det_hist_s   = 1'b1;
        det_hist_c   = 1'b0;
        det_path     = F18_S23_DET_CS;
      end
    end else if (flip_c_i) begin
      if (hist_c_q) begin
        det_path     = F18_S26_CC_REPEAT;          // S26: Y -> S24
      end else begin
        rot_detected = 1'b1;                       // S27, S28
        det_hist_c   = 1'b1;
        det_hist_s   = 1'b0;
        det_path     = F18_S28_DET_CC;
      end
    end
  end

  // ---- S6: shorten by T1, clamped at the minimum ([0260]-[0262], I10) ----
  always_comb begin
    shorter_si = (interval_q > cfg_i.t1) ? (interval_q - cfg_i.t1) : 16'd0;
    if (shorter_si < cfg_i.si_min) begin
      shorter_si = cfg_i.si_min;
    end
  end

  // ---- S10: expand by T2 (17-bit sum), clamped at x ([0260], I10) ----
  assign longer_sum = {1'b0, interval_q} + {1'b0, cfg_i.t2};
  always_comb begin
    longer_si = longer_sum[15:0];
    if (longer_sum > {1'b0, cfg_i.si_max}) begin
      longer_si = cfg_i.si_max;
    end
  end

  // ---- S9: CNTr + 1, saturating at 255 ([0248]) ----
  assign cnt_r_inc = (cnt_r_q == 8'hFF) ? 8'hFF : (cnt_r_q + 8'd1);

  // ---- FIG. 17 ----
  // Priority (spec 2.6): koff > no pulse (hold) > adaptive = 0 > Sr = 0 > FIG. 17/18.
  always_comb begin
    interval_d = interval_q;
    hist_s_d   = hist_s_q;
    hist_c_d   = hist_c_q;
    cnt_r_d    = cnt_r_q;
    fig17_o    = F17_IDLE;
    fig18_o    = F18_IDLE;

    if (key_fall_i) begin
      interval_d = si_max_next_i;                  // [0226]: start at x
      hist_s_d   = 1'b0;
      hist_c_d   = 1'b0;
      cnt_r_d    = 8'd0;                           // [0248]: count after the last detection
    end else if (pulse_i) begin
      if (!cfg_i.adaptive) begin
        interval_d = cfg_i.si_max;                 // fixed cycle T = x
        fig17_o    = F17_FIXED;
      end else if (!sr_i) begin
        fig17_o    = F17_S1_NO_RISE;               // S1: N, nothing changes
      end else begin
        fig18_o    = det_path;
        hist_s_d   = det_hist_s;
        hist_c_d   = det_hist_c;
        if (rot_detected) begin                    // S3: Y
          cnt_r_d = 8'd0;                          // S4
          if (interval_q <= cfg_i.si_min) begin
            fig17_o = F17_S5_AT_MIN;               // S5: Y ([0282], I11)
          end else begin
            interval_d = shorter_si;               // S6
            fig17_o    = F17_S6_SHORTEN;
          end
        end else if (interval_q >= cfg_i.si_max) begin
          fig17_o = F17_S7_AT_MAX;                 // S7: Y, the process ends
        end else if (cnt_r_q >= cfg_i.cth) begin   // S8: Y
          interval_d = longer_si;                  // S10
          hist_s_d   = 1'b0;                       // S11
          hist_c_d   = 1'b0;
          cnt_r_d    = cnt_r_inc;                  // S9
          fig17_o    = F17_S10_EXPAND;
        end else begin                             // S8: N
          cnt_r_d = cnt_r_inc;                     // S9
          fig17_o = F17_S9_COUNT;
        end
      end
    end
  end

  always_ff @(posedge clk or negedge rst_n) begin
    if (!rst_n) begin
      interval_q <= SI_RESET;
      hist_s_q   <= 1'b0;
      hist_c_q   <= 1'b0;
      cnt_r_q    <= 8'd0;
    end else begin
      interval_q <= interval_d;
      hist_s_q   <= hist_s_d;
      hist_c_q   <= hist_c_d;
      cnt_r_q    <= cnt_r_d;
    end
  end

  assign interval_o = interval_q;
  assign hist_s_o   = hist_s_q;
  assign hist_c_o   = hist_c_q;
  assign cnt_r_o    = cnt_r_q;

endmodule : pmu_interval_adapt
