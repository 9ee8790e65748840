// pmu_rail_monitor (idioms variant): the same activation signal Sr as ../pmu_rail_monitor.sv, written
// with two simulation idioms many teams keep in their RTL:
//   - an `initial` banner with a delay and $display;
//   - a unit delay on the nonblocking assignment of the flop (`q <= #1 d;`), so that waveforms
//     show the flop changing just after the clock edge.
// Neither changes the cycle behaviour: #1 is below the clock period and the banner drives
// nothing. Used only by pmu50_alt_idioms.f, instead of ../pmu_rail_monitor.sv.
//
// Sensor power determination unit 57 ([0209]-[0210]); I2, FIG. 17 S1-S2 ([0264]-[0265]);
// spec 2.3: sr <= vs2_en & vs2_ok.

module pmu_rail_monitor (
  input  logic clk,
  input  logic rst_n,
  input  logic vs2_en_i,    // unit 54 is outputting Vs2
  input  logic vs2_ok_i,    // analog power-good of Vs2
  output logic sr_o
);

  logic sr_q;

  initial #5 $display("pmu_rail_monitor: %m: Sr = Vs2 enable & Vs2 power-good (spec 2.3)");

  always_ff @(posedge clk or negedge rst_n) begin
    if (!rst_n) begin
      sr_q <= 1'b0;
    end else begin
      sr_q <= #1 vs2_en_i & vs2_ok_i;
    end
  end

  assign sr_o = sr_q;

endmodule : pmu_rail_monitor
