// pmu_keysync: ignition key synchronizer, operation switching signal Sig and its edges.
//
// Action switching unit 56a ([0213]): Sig follows IG; regulator 51 and supply units 52/53/54
// follow Sig ([0196]-[0208], [0335]-[0348]). Spec 2.1 and interpretation I1: IG is
// asynchronous, so it passes DEPTH flops; the last flop is Sig.

module pmu_keysync import pmu50_alt_pkg::*; #(
  parameter int unsigned DEPTH = 2            // SYNC_DEPTH, 1..4 (spec 1)
) (
  input  logic             clk,
  input  logic             rst_n,
  input  logic             ig_i,              // raw ignition key IG ([0080])
  output logic [DEPTH-1:0] stage_o,           // all stages, bit 0 first
  output logic             key_on_o,          // Sig ([0196]-[0198])
  output logic             key_rise_o,        // Sig rises at this edge (comb, "kon")
  output logic             key_fall_o         // Sig falls at this edge (comb, "koff")
);

  logic [DEPTH-1:0] stage_q;
  logic [DEPTH-1:0] stage_d;

  // One flop per stage; stage 0 samples IG, stage i the stage before it.
  for (genvar i = 0; i < DEPTH; i++) begin : g_stage
    if (i == 0) begin : g_head
      assign stage_d[i] = ig_i;
    end else begin : g_tail
      assign stage_d[i] = stage_q[i-1];
    end

    always_ff @(posedge clk or negedge rst_n) begin
      if (!rst_n) begin
        stage_q[i] <= 1'b0;
      end else begin
        stage_q[i] <= stage_d[i];
      end
    end
  end : g_stage

  assign stage_o    = stage_q;
  assign key_on_o   = stage_q[DEPTH-1];
  // kon / koff of spec 2.1: compare the last stage now with its value after the edge.
  assign key_rise_o = ~stage_q[DEPTH-1] &  stage_d[DEPTH-1];
  assign key_fall_o =  stage_q[DEPTH-1] & ~stage_d[DEPTH-1];

endmodule : pmu_keysync
