from urdfgen import *
d1,a2,a3,d4,d5,d6=0.1273,-0.612,-0.5723,0.163941,0.1157,0.0922
h=PI/2; L=2*PI
parts=[
 link("base_link",4.0,[col(("cyl",(0.075,0.12)),(0,0,0.06))]),
 link("shoulder_link",7.778,[col(("cyl",(0.075,0.24)),(0,-0.11,d1),(h,0,0))]),
 joint("shoulder_pan_joint","base_link","shoulder_link",kind="revolute",lim=(-L,L),vel=2.0944,eff=330),
 link("upper_arm_link",12.93,[col(("cyl",(0.06,0.612)),(a2/2,0,0.176),(0,h,0))]),
 joint("shoulder_lift_joint","shoulder_link","upper_arm_link",(0,0,d1),(h,0,0),"revolute",lim=(-L,L),vel=2.0944,eff=330),
 link("forearm_link",3.87,[col(("cyl",(0.045,0.5723)),(a3/2,0,0.049),(0,h,0))]),
 joint("elbow_joint","upper_arm_link","forearm_link",(a2,0,0),kind="revolute",lim=(-PI,PI),vel=3.1416,eff=150),
 link("wrist_1_link",1.96,[col(("cyl",(0.046,0.21)),(0,0,0.107))]),
 joint("wrist_1_joint","forearm_link","wrist_1_link",(a3,0,0),kind="revolute",lim=(-L,L),vel=3.1416,eff=56),
 link("wrist_2_link",1.96,[col(("cyl",(0.046,0.12)),(0,0,0.05))]),
 joint("wrist_2_joint","wrist_1_link","wrist_2_link",(0,0,d4),(h,0,0),"revolute",lim=(-L,L),vel=3.1416,eff=56),
 link("wrist_3_link",0.202,[col(("cyl",(0.046,0.08)),(0,0,0.045))]),
 joint("wrist_3_joint","wrist_2_link","wrist_3_link",(0,0,d5),(-h,0,0),"revolute",lim=(-L,L),vel=3.1416,eff=56),
 link("tool0",0.01),
 joint("flange_joint","wrist_3_link","tool0",(0,0,d6)),
 link("gripper_base",1.0,[col(("box",(0.085,0.09,0.10)),(0,0,0.05))]),
 joint("gripper_mount","tool0","gripper_base"),
 # Fingers: the joint value is the distance of each finger's inner face from the centre
 # line (0 closed, 0.0475 fully open); the right finger mimics the left.
 link("left_finger",0.05,[col(("box",(0.02,0.012,0.06)),(0,0.006,0.03))]),
 joint("finger_joint","gripper_base","left_finger",(0,0,0.10),kind="prismatic",axis=(0,1,0),lim=(0,0.0475),vel=0.1,eff=45),
 link("right_finger",0.05,[col(("box",(0.02,0.012,0.06)),(0,-0.006,0.03))]),
 joint("right_finger_joint","gripper_base","right_finger",(0,0,0.10),kind="prismatic",axis=(0,1,0),lim=(-0.0475,0),vel=0.1,eff=45,mimic=("finger_joint",-1)),
 link("gripper_tcp",0.001),
 joint("tcp_joint","gripper_base","gripper_tcp",(0,0,0.13)),
]
open(__import__("os").path.join(__import__("os").path.dirname(__file__), "../../domains/robots/ur10_ag95.urdf"),"w").write(robot("ur10_ag95",
 "UR10 (published DH parameters: d1 0.1273, a2 -0.612, a3 -0.5723, d4 0.163941,\n     d5 0.1157, d6 0.0922 m; joint limits +-2 pi as the datasheet, the elbow +-pi as ROS\n     ur_description restricts it against self-collision; speeds 120 and 180 deg/s) with a\n     parallel gripper modelled on the DH AG-95: 95 mm stroke, 12 mm thick fingers on one\n     prismatic joint (finger_joint: inner face to centre line, 0 to 0.0475 m; the right\n     finger mimics it), tool centre point 0.13 m past the flange between the fingertips. Joint\n     frames follow the DH convention, so FK(q) is the DH product. Collision geometry:\n     primitives sized to the links (approximate).", parts))
