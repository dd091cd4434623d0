"""Writes the text inputs of the bad-input corpus (tests/badinput/inputs/).

The inputs are committed; this script documents how each was made and
rewrites them (python3 tests/badinput/make_inputs.py). Inputs with bytes
that are not text (NULs, invalid UTF-8, /dev/zero, a 1 GiB sparse file)
are made at run time by run_badinput.py instead.
"""
import os
import random

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "inputs")

# a few RAV4 frames (tests/data/comma2k19-rav4/rav4_bus0.log), 10 ms apart
FRAMES = ["024#01FE01D541F980BB", "025#0000000000000000", "0AA#25B525B525A0258D", "0B4#000000001D0B7A5E"]
COLS = ["t_s", "wheel_speed_fl", "wheel_speed_fr", "wheel_speed_rl", "wheel_speed_rr", "steer_angle", "yaw_rate",
        "ax", "ay"]


def log_lines(n=40, t0=46408.5, dt=0.0025):
    return [f"({t0 + k * dt:017.6f}) vcan0 {FRAMES[k % 4]}" for k in range(n)]


def csv_rows(n=30, dt=0.01, t0=0.0, cols=COLS):
    rows = []
    for k in range(n):
        v = {"t_s": f"{t0 + k * dt:.6f}", "steer_angle": "0.01", "yaw_rate": "0.002", "ax": "0.1", "ay": "0.3"}
        rows.append(",".join(v.get(c, "20") for c in cols))
    return rows


def write(name, lines):
    with open(os.path.join(OUT, name), "w", newline="") as f:
        f.write("".join(l + "\n" for l in lines))


def main():
    os.makedirs(OUT, exist_ok=True)
    good = log_lines()
    # ---- candump logs
    shuffled = good[:]
    random.Random(7).shuffle(shuffled)
    write("shuffled.log", shuffled)
    back = good[:10]
    back.insert(6, "(00046408.505500) vcan0 024#01FE01D541F980BB")   # 7 ms behind line 6
    write("back_7ms.log", back)
    step = good[:8] + [l.replace("(0000046408.", "(0000046403.") for l in good[8:16]]   # clock stepped back 5 s
    write("clock_step_back.log", step)
    far = good[:4] + ["(00046406.000000) vcan0 024#01FE01D541F980BB"] + good[4:8]
    write("back_2500ms.log", far)
    write("empty.log", [])
    write("comments_only.log", ["# candump log", "", "   ", "# nothing else"])
    write("all_malformed.log", ["not a frame", "(1.0) vcan0 123#0G", "(1.0) vcan0"])
    write("long_line.log", good[:2] + ["(00046408.510000) vcan0 024#" + "0" * 600])
    cases = {
        "classic_9_bytes.log": "(00046408.510000) vcan0 024#01FE01D541F980BB00",
        "odd_digits.log": "(00046408.510000) vcan0 024#01FE01D541F980B",
        "bad_hex.log": "(00046408.510000) vcan0 024#01FE01D541F980BZ",
        "id_4_digits.log": "(00046408.510000) vcan0 0024#01FE01D541F980BB",
        "id_11bit_high.log": "(00046408.510000) vcan0 800#01FE01D541F980BB",
        "id_29bit_high.log": "(00046408.510000) vcan0 40000000#01",
        "fd_len_9.log": "(00046408.510000) vcan0 024##1" + "00" * 9,
        "fd_len_65.log": "(00046408.510000) vcan0 024##1" + "00" * 65,
        "fd_flags.log": "(00046408.510000) vcan0 024##G00",
        "no_paren.log": "00046408.510000 vcan0 024#01FE01D541F980BB",
        "no_fraction.log": "(00046408) vcan0 024#01FE01D541F980BB",
        "ts_13_digits.log": "(1000046408000.510000) vcan0 024#01FE01D541F980BB",
        "ts_10_fraction.log": "(00046408.5100000000) vcan0 024#01FE01D541F980BB",
        "no_iface.log": "(00046408.510000) ",
        "no_frame.log": "(00046408.510000) vcan0",
        "no_blank.log": "(00046408.510000)vcan0 024#01FE01D541F980BB",
        "trailing_text.log": "(00046408.510000) vcan0 024#01FE01D541F980BB extra",
        "dot_leading.log": "(00046408.510000) vcan0 024#.01FE01D541F980BB",
        "dot_double.log": "(00046408.510000) vcan0 024#01..FE01D541F980BB",
        "error_frame_4.log": "(00046408.510000) vcan0 20000040#00000000",
        "rtr_len_9.log": "(00046408.510000) vcan0 024#R9",
        "dlc_suffix.log": "(00046408.510000) vcan0 024#01FE_9",
        "cr_inside.log": "(00046408.510000) vcan0 024#01FE\r01D541F980BB",
        "iface_too_long.log": "(00046408.510000) " + "c" * 40 + " 024#01FE01D541F980BB",
    }
    for name, bad in cases.items():
        write(name, good[:3] + [bad] + good[3:5])
    # ---- signal table and vehicle file
    write("long_line.sigtab", ["grip-can-table 1 rav4", "# " + "x" * 600])
    write("unknown_input.sigtab", ["grip-can-table 1 t", "msg KINEMATICS 0x24 8 12000 none 0 0 0 intel",
                                   "sig YAW_RATE yaw_rte value 1 10 motorola 0 37 585297991 -299845282323 43 981"])
    # tables every line of which parses, but that fail the consistency check
    kin = ["grip-can-table 1 t", "msg KINEMATICS 0x24 8 12000 none 0 0 0 intel",
           "sig YAW_RATE yaw_rate value 1 10 motorola 0 37 585297991 -299845282323 43 981",
           "sig ACCEL_X ax value 17 10 motorola 0 34 -616585505 315680096256 95 929"]
    write("table_dup_id.sigtab", kin + ["msg STEER_ANGLE_SENSOR 0x24 8 12000 none 0 0 0 intel",
                                        "sig STEER_ANGLE steer_angle value 3 12 motorola 1 35 899535847 0 -333 333"])
    write("table_bits.sigtab", kin[:3] + [kin[3].replace(" value 17 10 ", " value 70 10 ")])
    write("table_two_msgs.sigtab", kin + ["msg STEER_ANGLE_SENSOR 0x25 8 12000 none 0 0 0 intel",
                                          "sig ACCEL_Y ax value 3 12 motorola 1 34 -616585505 315680096256 95 929"])
    write("dup_key.veh", ["mass = 1600", "iz = 2600", "mass = 1700"])
    write("unknown_key.veh", ["mass = 1600", "wheelbase = 2.7"])
    write("not_number.veh", ["mass = 1600 kg"])
    write("long_line.veh", ["mass = 1600 # " + "x" * 600])
    write("track_both.veh", ["track_f = 1.5", "track = 1.6"])
    # ---- CSV inputs (--csv)
    head = ",".join(COLS)
    write("typo_yawrate.csv", [head.replace("yaw_rate", "yawrate")] + csv_rows(3))
    write("dup_column.csv", [head + ",ay"] + [r + ",0.3" for r in csv_rows(3)])
    write("two_time.csv", [head + ",t"] + [r + ",0" for r in csv_rows(3)])
    write("missing_ax.csv", [",".join(c for c in COLS if c != "ax")] +
          csv_rows(3, cols=[c for c in COLS if c != "ax"]))
    write("no_time.csv", [",".join(COLS[1:])] + [r.split(",", 1)[1] for r in csv_rows(3)])
    write("empty_name.csv", [head + ","] + [r + "," for r in csv_rows(3)])
    write("unknown_far.csv", [head + ",gps_latitude"] + [r + ",47.1" for r in csv_rows(3)])
    write("quoted_header.csv", [head.replace("t_s", '"t_s"')] + csv_rows(3))
    write("upper_case.csv", [head.replace("ay", "AY")] + csv_rows(3))
    rows = csv_rows(5)
    write("short_row.csv", [head] + rows[:2] + [",".join(rows[2].split(",")[:6])] + rows[3:])
    write("long_row.csv", [head] + rows[:2] + [rows[2] + ",1"] + rows[3:])
    write("not_number.csv", [head] + rows[:3] + [rows[3].replace("0.002", "abc")])
    write("hex_number.csv", [head] + rows[:1] + [rows[1].replace("0.002", "0x10")] + rows[2:])
    write("bad_time.csv", [head] + rows[:2] + ["x" + rows[2][rows[2].index(","):]] + rows[3:])
    rows = csv_rows(30)
    write("time_backwards.csv", [head] + rows[:20] + [rows[18]] + rows[21:])
    write("time_repeated.csv", [head] + rows[:20] + [rows[19]] + rows[20:])
    write("missing_row.csv", [head] + rows[:20] + rows[21:])
    write("rate_25hz.csv", [head] + csv_rows(30, dt=0.04))
    write("rate_50hz.csv", [head] + csv_rows(30, dt=0.02))
    write("rate_97hz.csv", [head] + csv_rows(30, dt=0.0103))
    write("time_ms.csv", [head] + csv_rows(30, dt=10.0))
    drift = csv_rows(17) + csv_rows(100, dt=0.0104, t0=0.16 + 0.0104)
    write("rate_drift.csv", [head] + drift)
    write("header_only.csv", ["# inputs", head])
    write("empty.csv", [])
    write("comments_only.csv", ["# nothing", "#"])
    write("many_columns.csv", [head + "," + ",".join(f"c{k}" for k in range(300))])
    write("long_line.csv", [head] + csv_rows(2) + [csv_rows(3)[2] + "," + "9" * 9000])
    write("cr_only.csv", ["\r".join([head] + csv_rows(3))])
    write("good.csv", [head] + csv_rows(30))
    # ---- grip-tire: CSV rows on standard input
    th = "kappa,alpha,gamma,fz,p,vx"
    row = "0,0.01,0,4000,0,10"
    write("tire_good.csv", [th, row, row])
    write("tire_missing_col.csv", ["kappa,alpha,gamma,fz,p", "0,0.01,0,4000,0"])
    write("tire_dup_col.csv", [th + ",alpha", row + ",0.02"])
    write("tire_out_collision.csv", [th + ",fx", row + ",1"])
    write("tire_text_cell.csv", [th, row, "0,abc,0,4000,0,10"])
    write("tire_short_row.csv", [th, row, "0,0.01,0"])
    write("tire_quote.csv", [th + ",note", row + ',"open'])
    write("tire_empty.csv", [])
    # unit errors: loads in kN, slip angles in degrees, pressure in bar,
    # camber in degrees, a header that declares another unit
    write("tire_kn.csv", [th] + [f"0,{a / 100:.2f},0,{fz},0,10" for fz in (2, 4, 6) for a in (-4, 0, 4)])
    write("tire_degrees.csv", [th] + [f"0,{a},0,4000,0,10" for a in (0.5, 1, 2, 4, 8)])
    write("tire_bar.csv", [th, "0,0.01,0,4000,2.2,10", "0,0.01,0,4000,2.4,10"])
    write("tire_camber_deg.csv", [th, "0,0.01,3,4000,0,10"])
    write("tire_declared_kn.csv", ["kappa,alpha[rad],gamma,fz[kN],p,vx", "0,0.01,0,4,0,10"])
    # ---- .tir files the library rejects after the reader accepted them,
    # and brush-model parameter files (grip-tire --model ... --params)
    with open(os.path.join(HERE, "..", "data", "tir", "minimal.tir")) as f:
        minimal = f.read().splitlines()
    write("lib_fnomin.tir", [l.replace("FNOMIN = 4000", "FNOMIN = 2000000") for l in minimal])
    write("lib_lmuv.tir", [l.replace("FITTYP = 61          $ Magic Formula 6.1", "FITTYP = 61\nLONGVL = 0.1")
                           for l in minimal] + ["[SCALING_COEFFICIENTS]", "LMUV = 0.5"])
    write("brush_mu.txt", ["model = fiala", "mu = 4"])
    write("brush_mu_order.txt", ["model = sakai", "mu_s = 0.5", "mu_d = 0.9"])
    write("brush_default_fz.txt", ["model = neofiala", "fz_min = 20000"])
    write("brush_ok.txt", ["model = neofiala"])
    write("veh_mass.veh", ["mass = 0.5"])
    write("veh_steer.veh", ["steer_ratio = 200"])
    # beyond Q15.16 (the fixed build): converted to the format's bound, refused by the range
    write("veh_lf_huge.veh", ["lf = 100000"])
    # ---- measured-data CSV for the Python tools (grip fit-mf, grip analyze)
    fy = ["fz[N],alpha[rad],gamma[rad],fy[N]"] + [f"{fz},{a / 100:.3f},0,{-fz * a / 20:.1f}"
                                                 for fz in (2000, 4000, 6000) for a in range(-20, 21, 2)]
    write("fit_good.csv", fy)
    write("fit_nan.csv", fy[:4] + ["4000,nan,0,100"] + fy[5:])
    write("fit_kn.csv", [fy[0]] + [f"{fz},{a / 100:.3f},0,{-fz * a * 50:.1f}" for fz in (2, 4, 6)
                                   for a in range(-20, 21, 2)])
    # loads of a few hundred newtons: kN to a tyre with FNOMIN in the kN (a tenth of FNOMIN)
    write("fit_kn_fnomin.csv", [fy[0]] + [f"{fz},{a / 100:.3f},0,{-fz * a / 20:.1f}" for fz in (200, 300, 350)
                                          for a in range(-20, 21, 2)])
    write("fit_degrees.csv", [l.replace(",0.200,", ",20.0,") for l in fy])
    write("fit_typo.csv", [fy[0].replace("alpha[rad]", "alpah")] + fy[1:])
    write("fit_negative_load.csv", [l.replace("2000,", "-2000,") for l in fy])
    write("fit_three_rows.csv", fy[:4])
    write("fit_header_only.csv", fy[:1])
    t = ["t[s],alpha[rad],fz[N],fy[N]"] + [f"{i * 0.01:.2f},0.01,4000,-500" for i in range(50)]
    write("an_good.csv", t)
    write("an_time_back.csv", t[:10] + ["0.05,0.01,4000,-500"] + t[11:])
    write("an_no_output.csv", ["t[s],alpha[rad],fz[N]", "0,0.01,4000", "0.01,0.01,4000"])
    write("an_degrees.csv", [t[0]] + [f"{i * 0.01:.2f},{(i - 25) * 0.3:.1f},4000,{(25 - i) * 60}" for i in range(50)])
    write("an_kn.csv", [t[0]] + [f"{i * 0.01:.2f},0.01,4,-500" for i in range(50)])
    write("an_header_only.csv", t[:1])


if __name__ == "__main__":
    main()
