// pmu_count_check: count diagnosis in hardware.
//
// Diagnosis unit 67 judges the second sensor and the counters from the difference of CNTs and
// CNTc ([0118]-[0119], [0173]); the part in the PMU is a flag (I14, spec 2.7):
// diag <= |sext(CNTs - CNTc)| >= 2 or quadrant_skip, taken from the counters' next values so that
// the flag is aligned with the counts it describes.

module pmu_count_check import pmu50_alt_pkg::*; #(
  parameter int unsigned CNT_W = 16
) (
  input  logic             clk,
  input  logic             rst_n,
  input  logic [CNT_W-1:0] cnt_s_next_i,
  input  logic [CNT_W-1:0] cnt_c_next_i,
  input  logic             qskip_next_i,
  output logic             diag_o
);

  logic [CNT_W-1:0] delta;       // CNTs - CNTc modulo 2^CNT_W
  logic             delta_small; // sext(delta) in {-1, 0, +1}
  logic             diag_q;

  assign delta       = cnt_s_next_i - cnt_c_next_i;
  assign delta_small = (delta == '0) || (delta == CNT_W'(1)) || (delta == '1);

  always_ff @(posedge clk or negedge rst_n) begin
    if (!rst_n) begin
      diag_q <= 1'b0;
    end else begin
      diag_q <= ~delta_small | qskip_next_i;
    end
  end

  assign diag_o = diag_q;

endmodule : pmu_count_check
