import re,statistics,sys
truth=[0]*6+[None]*4+[-2,0,0,-2,0,-2,-2,0,-2,0,-2,0]
fresh_sp=[0,1,0,1,0,0,1,0,1,1,0,0,1,0,1,0,1,0,1,0,0,1]
truth+=[-2*x for x in fresh_sp]
names=sys.argv[1:]
data={n:open(f'/tmp/s3{n}.txt').read().splitlines()[:44] for n in names}
print("label        truth shift  cross  "+"  ".join(f"{n:>8s}" for n in names))
errs={n:[] for n in names}; rat={n:[] for n in names}; fam={n:0 for n in names}
for i in range(44):
    if truth[i] is None: continue
    row=[]
    for n in names:
        c,s,sh=map(float,re.search(r'cross\s+(\S+) sh\s+(\S+) shift\s+(\S+)',data[n][i]).groups())
        row.append(s); e=s-truth[i]; errs[n].append(abs(e)); rat[n].append(abs(e)/max(abs(sh),1))
        if 10<=i<22 and truth[i]==-2 and abs(e)<=0.5: fam[n]+=1
    lab=data[names[0]][i].split()[0]
    print(f"{lab:12s} {truth[i]:+3d} {sh:+7.2f} {c:+6.2f}  "+"  ".join(f"{v:+8.2f}" for v in row))
for n in names:
    print(f"{n:10s} median|e| {statistics.median(errs[n]):.2f} within0.5 {sum(e<=0.5 for e in errs[n])}/40 k(1.4826 med |e|/|shift|) {1.4826*statistics.median(rat[n]):.3f} family spacers within 0.5: {fam[n]}/6")
