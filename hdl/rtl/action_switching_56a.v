// Action switching unit 56a, regulator mode 51, rail enables (spec 2.1).
// [0196]-[0208], [0213], [0335]-[0348]
//
// `ig` is brought into the clock domain by a SYNC_DEPTH-flop synchronizer; `sig` is the last flop.
// kon / koff are the combinational "sig rises / falls at this edge" strobes.
`default_nettype none

module action_switching_56a #(
    parameter integer SYNC_DEPTH = 2
) (
    input  wire clk,
    input  wire rst_n,
    input  wire ig,
    output wire sig,
    output wire kon,
    output wire koff,
    output wire vr_hi,
    output wire vm_en,
    output wire vs1_en,
    output wire vp_en,
    output wire rail_hi
);
    reg  [SYNC_DEPTH-1:0] sync;
    wire [SYNC_DEPTH-1:0] sync_nxt;

    generate
        if (SYNC_DEPTH == 1) begin : g_one
            assign sync_nxt = ig;
        end else begin : g_chain
            assign sync_nxt = {sync[SYNC_DEPTH-2:0], ig};
        end
    endgenerate

`ifdef MUT_SYNC_SHORT
    // MUTANT: the synchronizer is one flop shorter than SYNC_DEPTH (sig taken one stage early).
    localparam SIG_BIT = (SYNC_DEPTH > 1) ? SYNC_DEPTH - 2 : 0;
`else
    localparam SIG_BIT = SYNC_DEPTH - 1;
`endif

    wire sig_nxt = sync_nxt[SIG_BIT];

    assign sig     = sync[SIG_BIT];
    assign kon     = !sig &&  sig_nxt;
`ifdef MUT_KOFF_RAW_IG
    // MUTANT: koff decoded from the raw ig, not the synchronizer (one path without its flops).
    assign koff    =  sig && !ig;
`else
    assign koff    =  sig && !sig_nxt;
`endif
    assign vr_hi   = sig;
    assign vm_en   = sig;
    assign vs1_en  = sig;
    assign rail_hi = sig;
    assign vp_en   = 1'b1;

    always @(posedge clk or negedge rst_n) begin
`ifdef MUT_SYNC_RESET_ONES
        // MUTANT: the synchronizer resets to all ones (the key reads on after reset).
        if (!rst_n) sync <= {SYNC_DEPTH{1'b1}};
`else
        if (!rst_n) sync <= {SYNC_DEPTH{1'b0}};
`endif
        else        sync <= sync_nxt;
    end
endmodule

`default_nettype wire
