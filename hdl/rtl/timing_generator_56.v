// Timing generator of 56 and output window of 54 (spec 2.2).
// [0318]-[0323], [0336], [0347], [0349], [0354]
//
// Key off: one intermittent output per drive interval si: st at tmr = 0, Vs2 on for
// Wt = Pw + Pi + Ps ticks, Ps window at the end of Wt, sampling strobe on the last tick of Ps.
// Key on: Vs2 continuous, strobe every smp_on ticks. kon/koff restart the timer.
// All outputs are decoded from registers only (tmr, sig, si and the parameter registers).
`default_nettype none

module timing_generator_56 (
    input  wire        clk,
    input  wire        rst_n,
    input  wire        sig,
    input  wire        kon,
    input  wire        koff,
    input  wire [15:0] si,
    input  wire [15:0] pw,
    input  wire [15:0] pi,
    input  wire [15:0] ps,
    input  wire [15:0] smp_on,
    output wire        st,
    output wire        vs2_en,
    output wire        ps_win,
    output wire        smp
);
    reg [15:0] tmr;

    // 18-bit sums: wide enough for any three 16-bit fields (legal sets stay below 2^16).
    wire [17:0] t        = {2'b00, tmr};
    wire [17:0] t_inc    = t + 18'd1;
    wire [17:0] ps_start = {2'b00, pw} + {2'b00, pi};
    wire [17:0] wt       = ps_start + {2'b00, ps};
    wire [17:0] period   = {2'b00, (sig ? smp_on : si)};

    assign st     = !sig && (tmr == 16'd0);
    assign vs2_en =  sig || (t < wt);
`ifdef MUT_PS_WIN_LE
    // MUTANT: the Ps window ends one tick late (<= instead of <).
    assign ps_win = !sig && (t >= ps_start) && (t <= wt);
`else
    assign ps_win = !sig && (t >= ps_start) && (t < wt);
`endif
`ifdef MUT_SMP_LATE
    // MUTANT: the key-off sampling strobe comes one tick late (first tick after Ps).
    assign smp    =  sig ? (t_inc == {2'b00, smp_on}) : (t == wt);
`else
    assign smp    =  sig ? (t_inc == {2'b00, smp_on}) : (t_inc == wt);
`endif

`ifdef MUT_EOC_EQ
    // MUTANT: the cycle ends at t + 1 == period only: a period written below the timer is missed.
    wire end_of_cycle = (t_inc == period);
`else
    wire end_of_cycle = (t_inc >= period);
`endif

    always @(posedge clk or negedge rst_n) begin
        if (!rst_n)                          tmr <= 16'd0;
`ifdef MUT_KON_NO_RESTART
        // MUTANT: the timer is not restarted when the key turns on (only at key-off).
        else if (koff || end_of_cycle)        tmr <= 16'd0;
`else
        else if (kon || koff || end_of_cycle) tmr <= 16'd0;
`endif
        else                                  tmr <= t_inc[15:0];
    end
endmodule

`default_nettype wire
