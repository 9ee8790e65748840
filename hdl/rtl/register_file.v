// Register file (spec 2.8): the MPU's view of the core.
// [0108], [0163], [0259], [0321]-[0323], [0349]
//
// - Parameters in force this cycle are the register values before the edge.
// - Registered read: rdata <= read(bus_addr) every cycle (one cycle latency).
// - Writes only while sig = 1, and a parameter write only when the parameter set with the new
//   value is legal (spec 4). Anything else is refused: registers unchanged, bus_err <= 1.
// - STATUS (0x14) is write-1-to-clear for bits 5 (quadrant_skip) and 9 (bus_err).
`default_nettype none

module register_file #(
    parameter integer SYNC_DEPTH = 2,
    parameter integer CNT_W      = 16,
    parameter integer ADAPTIVE   = 1,
    parameter integer PW         = 5,
    parameter integer PI         = 12,
    parameter integer PS         = 5,
    parameter integer SI_MAX     = 660,
    parameter integer SI_MIN     = 220,
    parameter integer T1         = 220,
    parameter integer T2         = 110,
    parameter integer CTH        = 4,
    parameter integer SMP_ON     = 10
) (
    input  wire             clk,
    input  wire             rst_n,
    // bus
    input  wire             bus_we,
    input  wire [7:0]       bus_addr,
    input  wire [15:0]      bus_wdata,
    output wire [15:0]      bus_rdata,
    output wire             bus_err_o,
    // status view (register values before the edge)
    input  wire             sig,
    input  wire [CNT_W-1:0] cnt_s,
    input  wire [CNT_W-1:0] cnt_c,
    input  wire [7:0]       cnt_r,
    input  wire [15:0]      si,
    input  wire             cs,
    input  wire             cc,
    input  wire             hist_s,
    input  wire             hist_c,
    input  wire             diag,
    input  wire             quadrant_skip,
    input  wire             vld,
    input  wire             sr,
    // parameters in force
    output wire             adaptive_o,
    output wire [15:0]      pw_o,
    output wire [15:0]      pi_o,
    output wire [15:0]      ps_o,
    output wire [15:0]      si_max_o,
    output wire [15:0]      si_min_o,
    output wire [15:0]      t1_o,
    output wire [15:0]      t2_o,
    output wire [7:0]       cth_o,
    output wire [15:0]      smp_on_o,
    output wire [15:0]      si_max_nxt,     // SI_MAX after this edge (a legal write counts)
    // W1C strobe of STATUS.quadrant_skip
    output wire             skip_clr
);
    localparam [7:0] A_ID      = 8'h00;
    localparam [7:0] A_VERSION = 8'h01;
    localparam [7:0] A_CTRL    = 8'h02;
    localparam [7:0] A_PW      = 8'h03;
    localparam [7:0] A_PI      = 8'h04;
    localparam [7:0] A_PS      = 8'h05;
    localparam [7:0] A_SI_MAX  = 8'h06;
    localparam [7:0] A_SI_MIN  = 8'h07;
    localparam [7:0] A_T1      = 8'h08;
    localparam [7:0] A_T2      = 8'h09;
    localparam [7:0] A_CTH     = 8'h0A;
    localparam [7:0] A_SMP_ON  = 8'h0B;
    localparam [7:0] A_CFG     = 8'h0C;
    localparam [7:0] A_CNT_S   = 8'h10;
    localparam [7:0] A_CNT_C   = 8'h11;
    localparam [7:0] A_CNT_R   = 8'h12;
    localparam [7:0] A_SI      = 8'h13;
    localparam [7:0] A_STATUS  = 8'h14;

    localparam [15:0] ID_VALUE      = 16'h5050;
    localparam [15:0] VERSION_VALUE = 16'h0001;
    localparam [2:0]  CFG_SYNC      = SYNC_DEPTH[2:0];
    localparam [4:0]  CFG_CNTW      = CNT_W[4:0];
    localparam [15:0] CFG_VALUE     = {3'b000, CFG_CNTW, 5'b00000, CFG_SYNC};

    // Reset values (Verilog parameters, spec 2.8 / 6.2 `// param` names).
    localparam        R_ADAPTIVE = (ADAPTIVE != 0);
    localparam [15:0] R_PW       = PW[15:0];
    localparam [15:0] R_PI       = PI[15:0];
    localparam [15:0] R_PS       = PS[15:0];
    localparam [15:0] R_SI_MAX   = SI_MAX[15:0];
    localparam [15:0] R_SI_MIN   = SI_MIN[15:0];
    localparam [15:0] R_T1       = T1[15:0];
    localparam [15:0] R_T2       = T2[15:0];
    localparam [7:0]  R_CTH      = CTH[7:0];
    localparam [15:0] R_SMP_ON   = SMP_ON[15:0];

    // Registers (names as the model's pmu50.register_file.<reg>).
    reg        adaptive;
    reg [15:0] pw;
    reg [15:0] pi;
    reg [15:0] ps;
    reg [15:0] si_max;
    reg [15:0] si_min;
    reg [15:0] t1;
    reg [15:0] t2;
    reg [7:0]  cth;
    reg [15:0] smp_on;
    reg        bus_err;
    reg [15:0] rdata;

    assign adaptive_o = adaptive;
    assign pw_o       = pw;
    assign pi_o       = pi;
    assign ps_o       = ps;
    assign si_max_o   = si_max;
    assign si_min_o   = si_min;
    assign t1_o       = t1;
    assign t2_o       = t2;
    assign cth_o      = cth;
    assign smp_on_o   = smp_on;
    assign bus_rdata  = rdata;
    assign bus_err_o  = bus_err;

    // ---------------------------------------------------------------- write decode
`ifdef MUT_WRITE_KEY_OFF
    // MUTANT: the key (MPU powered) is not checked: writes are accepted while sig = 0.
    wire key_ok = 1'b1;
`else
    wire key_ok = sig;
`endif
`ifdef MUT_STATUS_ADDR_4BIT
    // MUTANT: STATUS decoded from the low 4 address bits: a write to PI (0x04) is a W1C.
    wire status_w1c = bus_we && key_ok && (bus_addr[3:0] == A_STATUS[3:0]);
`else
    wire status_w1c = bus_we && key_ok && (bus_addr == A_STATUS);
`endif
`ifdef MUT_W1C_WRONG_BIT
    // MUTANT: the quadrant_skip W1C strobe is taken from bit 4 (diag) instead of bit 5.
    assign skip_clr = status_w1c && bus_wdata[4];
`else
    assign skip_clr = status_w1c && bus_wdata[5];
`endif
    wire   err_clr  = status_w1c && bus_wdata[9];

    wire wr_ctrl   = (bus_addr == A_CTRL);
    wire wr_pw     = (bus_addr == A_PW);
    wire wr_pi     = (bus_addr == A_PI);
    wire wr_ps     = (bus_addr == A_PS);
    wire wr_si_max = (bus_addr == A_SI_MAX);
    wire wr_si_min = (bus_addr == A_SI_MIN);
    wire wr_t1     = (bus_addr == A_T1);
    wire wr_t2     = (bus_addr == A_T2);
    wire wr_cth    = (bus_addr == A_CTH);
    wire wr_smp_on = (bus_addr == A_SMP_ON);
    wire is_param  = wr_ctrl | wr_pw | wr_pi | wr_ps | wr_si_max | wr_si_min |
                     wr_t1 | wr_t2 | wr_cth | wr_smp_on;

    // Candidate parameter set with the written value.
    wire        c_adaptive = wr_ctrl   ? bus_wdata[0]   : adaptive;
    wire [15:0] c_pw       = wr_pw     ? bus_wdata      : pw;
    wire [15:0] c_pi       = wr_pi     ? bus_wdata      : pi;
    wire [15:0] c_ps       = wr_ps     ? bus_wdata      : ps;
    wire [15:0] c_si_max   = wr_si_max ? bus_wdata      : si_max;
    wire [15:0] c_si_min   = wr_si_min ? bus_wdata      : si_min;
    wire [15:0] c_t1       = wr_t1     ? bus_wdata      : t1;
    wire [15:0] c_t2       = wr_t2     ? bus_wdata      : t2;
    wire [7:0]  c_cth      = wr_cth    ? bus_wdata[7:0] : cth;
    wire [15:0] c_smp_on   = wr_smp_on ? bus_wdata      : smp_on;

    // Legality (spec 4). Wt is summed in 18 bits (three 16-bit fields), so no sum can wrap.
    wire [17:0] c_wt       = {2'b00, c_pw} + {2'b00, c_pi} + {2'b00, c_ps};
    wire [15:0] c_shortest = c_adaptive ? c_si_min : c_si_max;
    wire c_legal = (c_ps != 16'd0) && (c_si_max != 16'd0) && (c_si_min != 16'd0) &&
                   (c_t1 != 16'd0) && (c_t2 != 16'd0) && (c_smp_on != 16'd0) &&
`ifdef MUT_MIN_EQ_MAX_REFUSED
                   // MUTANT: min = x refused (< instead of <=).
                   (c_cth != 8'd0) && (c_si_min < c_si_max) &&
`else
                   (c_cth != 8'd0) && (c_si_min <= c_si_max) &&
`endif
`ifndef MUT_PW_PI_ZERO_OK
                   ((c_pw != 16'd0) || (c_pi != 16'd0)) &&         // pw + pi >= 1
`endif
`ifdef MUT_WT_LEGAL_LE
                   // MUTANT: Wt equal to the shortest interval is accepted (<= instead of <).
                   (c_wt <= {2'b00, c_shortest});
`else
                   (c_wt < {2'b00, c_shortest});
`endif

    wire param_wr = bus_we && !status_w1c && is_param && key_ok && c_legal;
    wire refused  = bus_we && !status_w1c && !param_wr;
    assign si_max_nxt = param_wr ? c_si_max : si_max;

    // ---------------------------------------------------------------- read mux
    // CNT_S / CNT_C read sign-extended from CNT_W bits.
    wire [15:0] cnt_s_x;
    wire [15:0] cnt_c_x;
    generate
        if (CNT_W == 16) begin : g_full
            assign cnt_s_x = cnt_s;
            assign cnt_c_x = cnt_c;
        end else begin : g_sext
`ifdef MUT_CNT_READ_ZERO_EXT
            // MUTANT: CNT_S reads zero-extended (a negative count reads as a large positive one).
            assign cnt_s_x = {{(16 - CNT_W){1'b0}}, cnt_s};
`else
            assign cnt_s_x = {{(16 - CNT_W){cnt_s[CNT_W-1]}}, cnt_s};
`endif
            assign cnt_c_x = {{(16 - CNT_W){cnt_c[CNT_W-1]}}, cnt_c};
        end
    endgenerate
    wire [15:0] status_word = {6'b000000, bus_err, sr, vld, sig, quadrant_skip, diag,
                               hist_c, hist_s, cc, cs};
    reg  [15:0] rd;
    always @* begin
        case (bus_addr)
            A_ID:      rd = ID_VALUE;
            A_VERSION: rd = VERSION_VALUE;
            A_CTRL:    rd = {15'd0, adaptive};
            A_PW:      rd = pw;
            A_PI:      rd = pi;
            A_PS:      rd = ps;
`ifdef MUT_READ_SI_MAX_NEXT
            // MUTANT: SI_MAX reads its next value (a write in the read's cycle shows at once).
            A_SI_MAX:  rd = si_max_nxt;
`else
            A_SI_MAX:  rd = si_max;
`endif
            A_SI_MIN:  rd = si_min;
            A_T1:      rd = t1;
            A_T2:      rd = t2;
            A_CTH:     rd = {8'd0, cth};
            A_SMP_ON:  rd = smp_on;
            A_CFG:     rd = CFG_VALUE;
            A_CNT_S:   rd = cnt_s_x;
            A_CNT_C:   rd = cnt_c_x;
            A_CNT_R:   rd = {8'd0, cnt_r};
            A_SI:      rd = si;
            A_STATUS:  rd = status_word;
            default:   rd = 16'd0;
        endcase
    end

    // ---------------------------------------------------------------- registers
    always @(posedge clk or negedge rst_n) begin
        if (!rst_n) begin
            adaptive <= R_ADAPTIVE;
            pw       <= R_PW;
            pi       <= R_PI;
            ps       <= R_PS;
            si_max   <= R_SI_MAX;
            si_min   <= R_SI_MIN;
            t1       <= R_T1;
            t2       <= R_T2;
            cth      <= R_CTH;
            smp_on   <= R_SMP_ON;
            bus_err  <= 1'b0;
            rdata    <= 16'd0;
        end else begin
            if (param_wr) begin
                adaptive <= c_adaptive;
                pw       <= c_pw;
                pi       <= c_pi;
                ps       <= c_ps;
                si_max   <= c_si_max;
                si_min   <= c_si_min;
                t1       <= c_t1;
                t2       <= c_t2;
                cth      <= c_cth;
                smp_on   <= c_smp_on;
            end
            // Set wins over clear.
`ifdef MUT_ERR_CLEAR_WINS
            // MUTANT: the W1C clear of bus_err wins over a refusal on the same edge.
            bus_err <= !err_clr && (refused || bus_err);
`else
            bus_err <= refused || (bus_err && !err_clr);
`endif
            rdata   <= rd;
        end
    end
endmodule

`default_nettype wire
