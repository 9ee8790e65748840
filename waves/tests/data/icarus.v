`timescale 1ns/1ps
module tb;
  parameter P = 5;
  reg clk = 0; reg [7:0] cnt = 0; integer i = 3; real r = 1.5; event ev; wire [3:0] w = cnt[3:0];
  reg signed [15:0] s = -3; time tt; realtime rt;
  always #5 clk = ~clk;
  always @(posedge clk) begin cnt <= cnt + 1; r = r * 2.0; -> ev; tt = $time; rt = $realtime; end
  initial begin $dumpfile("t.vcd"); $dumpvars(0, tb); #100 r = 0.0/0.0; #20 $finish; end
endmodule
