// pmu_rail_monitor: activation signal Sr.
//
// Sensor power determination unit 57 ([0209]-[0210]) tells the rotation number detection unit
// that Vs2 is supplied. Interpretation I2 / FIG. 17 S1-S2 ([0264]-[0265]): the core sees the
// rise of Vs2 through the power-good input vs2_ok; Sr is registered, one tick late. Spec 2.3.

module pmu_rail_monitor (
  input  logic clk,
  input  logic rst_n,
  input  logic vs2_en_i,    // unit 54 is outputting Vs2
  input  logic vs2_ok_i,    // analog power-good of Vs2
  output logic sr_o
);

  logic sr_q;

  always_ff @(posedge clk or negedge rst_n) begin
    if (!rst_n) begin
      sr_q <= 1'b0;
    end else begin
      sr_q <= vs2_en_i & vs2_ok_i;
    end
  end

  assign sr_o = sr_q;

endmodule : pmu_rail_monitor
