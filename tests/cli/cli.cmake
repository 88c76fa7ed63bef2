# Command-line behaviour through CTest: expected output, and one clear message with exit status 2
# for every kind of bad input at start-up.
set(GPSEMU_EXPECT ${CMAKE_CURRENT_LIST_DIR}/expect.cmake)
function(gpsemu_cli_test name rc regex)
  list(JOIN ARGN "|" args)
  add_test(NAME cli.${name}
           COMMAND ${CMAKE_COMMAND} "-DCMD=$<TARGET_FILE:gpsemu>|${args}" -DRC=${rc} "-DREGEX=${regex}"
                   -P ${GPSEMU_EXPECT})
  set_tests_properties(cli.${name} PROPERTIES LABELS e2e)
endfunction()

file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/not_a_link.txt "a regular file the pty output must not replace\n")
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/bad_key.toml "rate = 5\nwidht = 2\n")
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/good.toml "# a config file\nrate = 5\nsource = \"sim:circle\"\noutput = \"stdout\"\n")

gpsemu_cli_test(version 0 "gpsemu [0-9]+\\.[0-9]+\\.[0-9]+" --version)
gpsemu_cli_test(help_lists_options 0 "--rate HZ.*--latency S.*--noise MODEL.*--width M.*--output SPEC" --help)
gpsemu_cli_test(unknown_flag 2 "bogus" --bogus)
gpsemu_cli_test(rate_zero 2 "--rate: rate must be from 0.1 to 50" --rate 0)
gpsemu_cli_test(rate_off_grid 2 "--rate: rate 2.5 Hz" --rate 2.5)
gpsemu_cli_test(rate_not_a_number 2 "--rate: rate expects a number" --rate fast)
gpsemu_cli_test(bad_origin 2 "--origin: origin latitude 91" --origin 91,0,0)
gpsemu_cli_test(origin_below_pose_range 2 "--origin: origin altitude -7000000 m is outside \\[-10000, 1000000\\] m"
                --origin 43,-89,-7000000 --fast --duration 1 --output stdout)
gpsemu_cli_test(origin_above_pose_range 2 "--origin: origin altitude 1000000000 m" --origin 0,0,1e9 --fast --duration 1 --output stdout)
gpsemu_cli_test(bad_noise 2 "unknown noise model 'pink'" --noise pink)
gpsemu_cli_test(bad_start_time 2 "'tomorrow'" --start-time tomorrow)
gpsemu_cli_test(missing_config 2 "/nonexistent/gpsemu.toml" --config /nonexistent/gpsemu.toml)
gpsemu_cli_test(config_unknown_key 2 "bad_key.toml:2: unknown key 'widht'" --config ${CMAKE_CURRENT_BINARY_DIR}/bad_key.toml)
gpsemu_cli_test(config_file_runs 0 "\\$GNRMC,120001\\.00,.*\\$GNGGA,120001\\.00" --config
                ${CMAKE_CURRENT_BINARY_DIR}/good.toml --fast --duration 1 --start-time 2024-05-01T12:00:01Z)
gpsemu_cli_test(unknown_source 2 "unknown simulator scenario 'sim:spiral'" --source sim:spiral --fast --output stdout)
gpsemu_cli_test(missing_waypoints 2 "/nonexistent/route.csv" --source sim:waypoints:/nonexistent/route.csv --fast --output stdout)
# --source mavlink:...: a malformed spec is one message naming it and exit status 2.
gpsemu_cli_test(mavlink_no_transport 2 "--source mavlink:5760: a MAVLink source is mavlink:udp:.*PORT [(]listen[)] or mavlink:tcp:HOST:PORT [(]connect[)]"
                --source mavlink:5760 --output stdout --duration 1)
gpsemu_cli_test(mavlink_serial 2 "--source mavlink:serial:/dev/ttyACM0: a MAVLink source is" --source mavlink:serial:/dev/ttyACM0 --duration 1)
gpsemu_cli_test(mavlink_bad_port 2 "--source mavlink:udp:70000:" --source mavlink:udp:70000 --duration 1)
gpsemu_cli_test(mavlink_tcp_port_zero 2 "--source mavlink:tcp:127.0.0.1:0: mavlink:tcp connects to a port" --source mavlink:tcp:127.0.0.1:0 --duration 1)
gpsemu_cli_test(mavlink_tcp_unknown_host 2 "cannot connect to tcp:no-such-host.invalid:5760: host 'no-such-host.invalid'"
                --source mavlink:tcp:no-such-host.invalid:5760 --output stdout --duration 1)
gpsemu_cli_test(mavlink_fast 2 "--source mavlink:udp:14550: a socket source runs on the wall clock" --source mavlink:udp:14550 --fast --duration 1)
gpsemu_cli_test(mavlink_lockstep 2 "--clock lockstep follows a simulator's time stamps: it needs a udp: or tcp: source, not --source mavlink:udp:14550"
                --source mavlink:udp:14550 --clock lockstep --duration 1)
gpsemu_cli_test(bad_output_spec 2 "bogus:thing" --output bogus:thing --fast --duration 1)
gpsemu_cli_test(pty_link_dir_missing 2 "/nonexistent/dir/gps" --output pty:/nonexistent/dir/gps --fast --duration 1)
gpsemu_cli_test(pty_link_is_a_file 2 "not_a_link.txt" --output pty:${CMAKE_CURRENT_BINARY_DIR}/not_a_link.txt --duration 1)
gpsemu_cli_test(stdout_stationary 0
                "\\$GNGGA,000000\\.00,4304\\.3[0-9]+,N,08924\\.7[0-9]+,W,1,[12][0-9],0\\.[4-9][0-9],2[56][0-9]\\.[0-9],M,-34\\.7,M,,\\*[0-9A-F][0-9A-F]"
                --fast --duration 2 --output stdout --start-time 2024-01-01T00:00:00Z)
gpsemu_cli_test(rate_needs_time_decimals 2 "repeat a time" --rate 20 --time-decimals 1)
# Sentence set, receiver states and fix quality (see core_receiver_states_test for the details).
gpsemu_cli_test(sentences_in_receiver_order 0
                "^\\$GNRMC,[^$]*\\$GNGGA,[^$]*\\$GNGST,[^$]*\\$GNZDA,[^$]*\\$GNRMC"
                --fast --duration 2 --output stdout --sentences ZDA,GST,GGA,RMC --log-level warn)
gpsemu_cli_test(bad_sentence 2 "--sentences: sentences: unknown sentence 'GXX'" --sentences GGA,GXX)
gpsemu_cli_test(bad_outage 2 "--outage: outage: expected START\\+DURATION" --outage 10)
gpsemu_cli_test(bad_fix_quality 2 "--fix-quality: fix-quality" --fix-quality ppp)
gpsemu_cli_test(bad_protocol 2 "gpsemu: --protocol: protocol must be one of nmea, ubx, nmea\\+ubx, got 'ubx2'" --protocol ubx2)
gpsemu_cli_test(bad_receiver 2 "gpsemu: --receiver: receiver must be one of generic, ublox-m8n, ublox-m9n, ublox-f9p, ublox-m10, got 'ublox-m7'"
                --receiver ublox-m7)
gpsemu_cli_test(outage_has_empty_fields 0 "\\$GNGGA,000001\\.00,,,,,0,00,99\\.99,,,,,,\\*[0-9A-F]+[^$]*\\$GNGSA,A,1,[^$]*\\$GPGSV,1,1,00,1\\*64"
                --fast --duration 3 --output stdout --outage 1+1 --start-time 2024-01-01T00:00:00Z --log-level warn)
gpsemu_cli_test(rtk_fixed_quality 0 "\\$GNGGA,[0-9.]+,[0-9.]+,N,[0-9.]+,W,4,.*\\$GNGLL,[^$]*,A,R\\*"
                --fast --duration 1 --output stdout --fix-quality rtk-fixed --log-level warn)
# A u-blox port writes no HDT or THS (they are not u-blox sentences): refused at start-up, not dropped.
gpsemu_cli_test(ublox_refuses_hdt 2 "sentences: a u-blox ublox-f9p does not write HDT"
                --receiver ublox-f9p --sentences GGA,HDT --fast --duration 1 --output stdout)
gpsemu_cli_test(ublox_refuses_ths 2 "sentences: a u-blox ublox-m9n does not write THS"
                --receiver ublox-m9n --protocol nmea+ubx --sentences RMC,THS --fast --duration 1 --output stdout)
gpsemu_cli_test(ublox_nmea_only_writes_hdt 0 "\\$GNHDT,"
                --receiver ublox-f9p --protocol nmea --sentences GGA,HDT --fast --duration 1 --output stdout)

# A value option before a subcommand's positional argument takes one value, not the argument too.
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/two_epochs.nmea
     "$GPGGA,120000.00,4304.35012,N,08924.75027,W,1,11,0.92,260.1,M,0.0,M,,*75\n$GPGGA,120001.00,4304.35012,N,08924.75027,W,1,11,0.92,260.1,M,0.0,M,,*74\n")
gpsemu_cli_test(replay_option_before_log 0 "GPGGA,120000\\.00.*GPGGA,120001\\.00"
                replay --speed 10 ${CMAKE_CURRENT_BINARY_DIR}/two_epochs.nmea --output stdout)
gpsemu_cli_test(replay_option_without_replay 2 "--speed applies to 'gpsemu replay LOG' only" --speed 10 --fast --duration 1)

# Many receivers in one process (core_fleet_test and core_fleet_e2e_test for the details).
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/fleet_rate.toml "[[receiver]]\nsource = \"sim:line\"\nrate = 5\n")
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/fleet_two.toml
     "[[receiver]]\noutput = \"file:fleet_a.nmea\"\n[[receiver]]\noutput = \"file:fleet_b.nmea\"\n")
gpsemu_cli_test(fleet_shared_output 2 "output 'pty:/tmp/gpsemu' would be shared by all 3 receivers.*put [{]i[}]"
                --receivers 3 --fast --duration 1)
gpsemu_cli_test(fleet_shared_source 2 "source 'udp:5600' would be shared by all 2 receivers.*udp:[{]5600[+]i[}]"
                --receivers 2 --source udp:5600 --output pty:/tmp/gpsemu-cli-fleet{i} --duration 1)
gpsemu_cli_test(fleet_shared_mavlink_source 2 "source 'mavlink:udp:14550' would be shared by all 2 receivers.*mavlink:udp:[{]14550[+]i[}]"
                --receivers 2 --source mavlink:udp:14550 --output pty:/tmp/gpsemu-cli-fleet{i} --duration 1)
gpsemu_cli_test(fleet_duplicate_port 2 "receiver 0 [(]source 'tcp:7001'[)] and receiver 1 [(]output 'tcp:7001'[)] would both listen on tcp port 7001"
                --receivers 3 --output tcp:{7000+i} --source tcp:{7001+i} --duration 1)
gpsemu_cli_test(fleet_bad_template 2 "output 'file:out[{]j[}]': '[{]j[}]' is not a receiver template"
                --receivers 2 --output file:out{j} --fast --duration 1)
gpsemu_cli_test(fleet_process_key_in_table 2
                "fleet_rate.toml:3: key 'rate' cannot be set in a \\[\\[receiver\\]\\] table: all receivers of a process share one epoch timeline"
                --config ${CMAKE_CURRENT_BINARY_DIR}/fleet_rate.toml --fast --duration 1)
gpsemu_cli_test(fleet_receivers_not_tables 2 "receivers is 3 but config file .*fleet_two.toml has 2 \\[\\[receiver\\]\\] tables"
                --config ${CMAKE_CURRENT_BINARY_DIR}/fleet_two.toml --receivers 3 --fast --duration 1)
gpsemu_cli_test(fleet_not_for_replay 2 "apply to the emulator loop, not to 'gpsemu replay'"
                replay --receivers 2 --output file:fleet{i}.nmea ${CMAKE_CURRENT_BINARY_DIR}/two_epochs.nmea)
# Issue 22, point 11: a number for a text option in a config file is refused even when the command
# line gives the option too (it was silently replaced by --output); a run in which no output took
# any epoch (every write failed) exits with status 3.
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/output_number.toml "output = 5\n")
gpsemu_cli_test(config_output_number 2 "output_number.toml:1: key 'output': expected a string \\(SPEC\\), got an integer"
                --config ${CMAKE_CURRENT_BINARY_DIR}/output_number.toml --output stdout --fast --duration 1)
gpsemu_cli_test(no_output_took_any_epoch 3 "no output took any epoch \\(every write failed\\): exit status 3"
                --output file:/dev/full --fast --duration 2)
# The bench view (docs/ui.md): a bad address, a short token and a port another server holds.
gpsemu_cli_test(ui_bad_port 2 "--ui: ui: expected \\[HOST:\\]PORT with PORT 0..65535, e.g. 8080, got '99999'" --ui 99999)
gpsemu_cli_test(ui_short_token 2 "--ui-token: ui-token: expected at least 8 characters" --ui 0 --ui-token abc)
gpsemu_cli_test(ui_not_an_address 2 "ui 192.0.2.1:0: cannot listen" --ui 192.0.2.1:0 --fast --duration 1 --output stdout)
