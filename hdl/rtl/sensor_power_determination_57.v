// Sensor power determination unit 57 (spec 2.3).
// [0209]-[0210], FIG. 17 S1-S2 [0264]-[0265]
//
// Sr is 1 while Vs2 is enabled and its power-good is high (registered: one tick late).
`default_nettype none

module sensor_power_determination_57 (
    input  wire clk,
    input  wire rst_n,
    input  wire vs2_en,
    input  wire vs2_ok,
    output reg  sr
);
    always @(posedge clk or negedge rst_n) begin
`ifdef MUT_SR_RESET_ONE
        // MUTANT: Sr resets to 1.
        if (!rst_n) sr <= 1'b1;
`else
        if (!rst_n) sr <= 1'b0;
`endif
`ifdef MUT_SR_IGNORES_VS2_OK
        // MUTANT: the power-good of Vs2 is ignored (a dead rail still "rises").
        else        sr <= vs2_en;
`elsif MUT_SR_PG_LATCHED
        // MUTANT: the power-good is latched while Vs2 is on: a Vs2 fault after Sr rose is missed.
        else        sr <= vs2_en && (vs2_ok || sr);
`else
        else        sr <= vs2_en && vs2_ok;
`endif
    end
endmodule

`default_nettype wire
