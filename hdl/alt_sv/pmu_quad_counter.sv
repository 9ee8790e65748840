// pmu_quad_counter: sine counter 58c and cosine counter 58d.
//
// Counting rules [0094]-[0099] (spec 2.5): when only Cs changes, CNTs counts up if the new Cs
// equals Cc, else down ([0096]-[0097]); when only Cc changes, CNTc counts up if the new Cc differs
// from Cs, else down ([0098]-[0099]). Both changing in one sample is a skipped quadrant: the
// counters hold and the sticky quadrant_skip is set (I5). The first sample after reset presets
// the counters from the quadrant, so CNT mod 4 is the quadrant index (I6, [0092]-[0093],
// [0142]). Counters wrap at CNT_W bits and run on Vp ([0211]): key-off never clears them.

module pmu_quad_counter import pmu50_alt_pkg::*; #(
  parameter int unsigned CNT_W = 16
) (
  input  logic             clk,
  input  logic             rst_n,
  input  logic             first_i,       // first sample since reset
  input  logic             sign_s_i,      // Cs before the edge
  input  logic             sign_c_i,      // Cc before the edge
  input  logic             sign_s_new_i,  // Cs after the edge
  input  logic             sign_c_new_i,  // Cc after the edge
  input  logic             flip_s_i,      // Cs changes at a counted sample
  input  logic             flip_c_i,      // Cc changes at a counted sample
  input  logic             qskip_clr_i,   // STATUS W1C bit 5
  output logic [CNT_W-1:0] cnt_s_o,
  output logic [CNT_W-1:0] cnt_c_o,
  output logic [CNT_W-1:0] cnt_s_next_o,  // next values, for the count diagnosis
  output logic [CNT_W-1:0] cnt_c_next_o,
  output logic             qskip_o,
  output logic             qskip_next_o
);

  logic [CNT_W-1:0] cnt_s_q, cnt_s_d;
  logic [CNT_W-1:0] cnt_c_q, cnt_c_d;
  logic             qskip_q, qskip_d;
  logic             both;

  assign both = flip_s_i & flip_c_i;

  always_comb begin
    cnt_s_d = cnt_s_q;
    cnt_c_d = cnt_c_q;
    if (first_i) begin
      // Preset from the first sampled quadrant (Cs, Cc):
      // (1,1) -> (0,0); (1,0) -> (0,1); (0,0) -> (1,1); (0,1) -> (1,2).
      unique case ({sign_s_new_i, sign_c_new_i})
        2'b11:   begin cnt_s_d = CNT_W'(0); cnt_c_d = CNT_W'(0); end
        2'b10:   begin cnt_s_d = CNT_W'(0); cnt_c_d = CNT_W'(1); end
        2'b00:   begin cnt_s_d = CNT_W'(1); cnt_c_d = CNT_W'(1); end
        default: begin cnt_s_d = CNT_W'(1); cnt_c_d = CNT_W'(2); end
      endcase
    end else if (flip_s_i && !both) begin
      if (sign_s_new_i == sign_c_i) cnt_s_d = cnt_s_q + CNT_W'(1);   // [0096] up, [0097] up
      else                          cnt_s_d = cnt_s_q - CNT_W'(1);   // [0096] down, [0097] down
    end else if (flip_c_i && !both) begin
      if (sign_c_new_i != sign_s_i) cnt_c_d = cnt_c_q + CNT_W'(1);   // [0098] up, [0099] up
      else                          cnt_c_d = cnt_c_q - CNT_W'(1);   // [0098] down, [0099] down
    end
  end

  // Sticky skip, cleared by STATUS W1C; a new skip wins over the clear ([0119], I5).
  assign qskip_d = both | (qskip_q & ~qskip_clr_i);

  always_ff @(posedge clk or negedge rst_n) begin
    if (!rst_n) begin
      cnt_s_q <= '0;
      cnt_c_q <= '0;
      qskip_q <= 1'b0;
    end else begin
      cnt_s_q <= cnt_s_d;
      cnt_c_q <= cnt_c_d;
      qskip_q <= qskip_d;
    end
  end

  assign cnt_s_o      = cnt_s_q;
  assign cnt_c_o      = cnt_c_q;
  assign cnt_s_next_o = cnt_s_d;
  assign cnt_c_next_o = cnt_c_d;
  assign qskip_o      = qskip_q;
  assign qskip_next_o = qskip_d;

endmodule : pmu_quad_counter
